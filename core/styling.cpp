#include "core/styling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <deque>

#include "core/color.h"
#include "core/colormap.h"
#include "core/derived_attributes.h"
#include "core/error.h"

namespace tc {

float evaluateTransferFunction(const std::vector<glm::vec2>& points, float t) {
    if (points.empty()) return 1.0f;
    if (std::isnan(t) || t <= points.front().x) return points.front().y;
    for (std::size_t i = 1; i < points.size(); ++i)
        if (t <= points[i].x) {
            float w = points[i].x - points[i - 1].x;
            return w > 0 ? glm::mix(points[i - 1].y, points[i].y, (t - points[i - 1].x) / w) : points[i].y;
        }
    return points.back().y;
}

float percentile(const std::vector<float>& values, float p) {
    std::vector<float> finite;
    finite.reserve(values.size());
    for (float v : values)
        if (std::isfinite(v)) finite.push_back(v);
    if (finite.empty()) return std::numeric_limits<float>::quiet_NaN();
    double position = std::clamp(double(p), 0.0, 100.0) / 100.0 * double(finite.size() - 1);
    std::size_t k = std::size_t(position);
    std::nth_element(finite.begin(), finite.begin() + std::ptrdiff_t(k), finite.end());
    double lo = finite[k];
    if (k + 1 >= finite.size()) return float(lo);
    double hi = *std::min_element(finite.begin() + std::ptrdiff_t(k) + 1, finite.end());
    return float(lo + (position - double(k)) * (hi - lo));
}

const Colormap& styleColormap(const ColorSpec& color, const std::string& sceneFile) {
    if (color.preset) return *color.preset;
    if (isBuiltinColormap(color.colormap)) return builtinColormap(color.colormap);
    throw InputError((sceneFile.empty() ? std::string("scene") : sceneFile) + ": style.color.colormap: preset \"" +
                     color.colormap + "\" was not loaded");
}

namespace {

std::string where(const std::string& sceneFile) {
    return sceneFile.empty() ? std::string("scene") : sceneFile;
}

// The dataset's attribute, else a derived one computed into `derived` (which owns it).
const Attribute& requireAttribute(const LineSet& lines, const std::string& name, const std::string& sceneFile,
                                  const std::string& key, std::deque<Attribute>& derived) {
    if (const Attribute* a = lines.attribute(name)) return *a;
    for (const Attribute& a : derived)
        if (a.name == name) return a;
    if (isDerivedAttribute(name)) {
        try {
            derived.push_back(computeDerivedAttribute(lines, name));
        } catch (const InputError& e) {
            throw InputError(where(sceneFile) + ": " + key + ": " + e.what());
        }
        return derived.back();
    }
    std::string available;
    for (const auto& a : lines.attributes) available += (available.empty() ? "" : ", ") + a.name;
    std::string derivable;
    for (const auto& n : derivedAttributeNames()) derivable += (derivable.empty() ? "" : ", ") + n;
    throw InputError(where(sceneFile) + ": " + key + ": the dataset has no attribute \"" + name +
                     "\" (available: " + (available.empty() ? "none" : available) + "; derived: " + derivable + ")");
}

ValueRange mappingRange(const Attribute& a, const RangeSpec& r) {
    ValueRange range;
    if (r.percentiles) {
        range = {percentile(a.values, r.percentileLo), percentile(a.values, r.percentileHi)};
    } else {
        range = {r.automatic ? a.min : r.lo, r.automatic ? a.max : r.hi};
    }
    if (!std::isfinite(range.lo) || !std::isfinite(range.hi)) range = {0.0f, 0.0f};
    return range;
}

// Normalised attribute value in [0,1] for a range; NaN stays NaN.
struct Normalizer {
    float lo = 0, scale = 0;
    Normalizer() = default;
    Normalizer(const Attribute& a, const RangeSpec& r) {
        const ValueRange range = mappingRange(a, r);
        lo = range.lo;
        scale = range.hi > range.lo ? 1.0f / (range.hi - range.lo) : 0.0f;
    }
    float operator()(float v) const { return std::isnan(v) ? v : std::clamp((v - lo) * scale, 0.0f, 1.0f); }
};

// style.color "direction": |t| of the unit tangent at each vertex (the chord through its two
// neighbours; the one segment at polyline ends) as an sRGB colour, the alpha kept.
void directionColors(const LineSet& lines, std::vector<glm::vec4>& color) {
    tbb::parallel_for(std::size_t(0), lines.polylineCount(), [&](std::size_t p) {
        const std::uint32_t begin = lines.offsets[p], end = lines.offsets[p + 1];
        for (std::uint32_t v = begin; v < end; ++v) {
            const glm::vec3 d = lines.positions[std::min(v + 1, end - 1)] - lines.positions[v > begin ? v - 1 : v];
            const float length = glm::length(d);
            const glm::vec3 rgb = length > 0.0f ? glm::abs(d / length) : glm::vec3(0.5f);
            color[v] = glm::vec4(srgbToLinear(rgb), color[v].w);
        }
    });
}

}  // namespace

std::optional<ValueRange> colorMappingRange(const LineSet& lines, const StyleSpec& style,
                                            const std::string& sceneFile) {
    if (style.color.attribute.empty() || style.color.direction) return std::nullopt;
    std::deque<Attribute> derived;
    return mappingRange(requireAttribute(lines, style.color.attribute, sceneFile, "style.color.attribute", derived),
                        style.color.range);
}

StyledLines styleLines(const LineSet& lines, const StyleSpec& style, const std::string& sceneFile) {
    StyledLines out;
    const std::size_t n = lines.vertexCount();
    out.positionRadius.resize(n);
    out.color.resize(n);
    out.polylineId.resize(n);
    out.flags.assign(n, 0u);

    std::deque<Attribute> derived;  // a deque: references to earlier elements stay valid
    const Attribute* radiusAttr =
        style.radius.attribute.empty()
            ? nullptr
            : &requireAttribute(lines, style.radius.attribute, sceneFile, "style.radius.attribute", derived);
    const Attribute* colorAttr =
        style.color.attribute.empty()
            ? nullptr
            : &requireAttribute(lines, style.color.attribute, sceneFile, "style.color.attribute", derived);
    const Attribute* opacityAttr =
        style.opacity.attribute.empty()
            ? nullptr
            : &requireAttribute(lines, style.opacity.attribute, sceneFile, "style.opacity.attribute", derived);
    const Colormap* colormap =
        colorAttr || style.opacity.pointsFromColormap ? &styleColormap(style.color, sceneFile) : nullptr;
    const std::vector<glm::vec2>* opacityPoints = &style.opacity.points;
    if (opacityAttr && style.opacity.pointsFromColormap) {
        if (colormap->opacity.empty())
            throw InputError(where(sceneFile) + ": style.opacity.points: the colormap \"" + style.color.colormap +
                             "\" has no opacity points");
        opacityPoints = &colormap->opacity;
    }
    Normalizer radiusN = radiusAttr ? Normalizer(*radiusAttr, style.radius.range) : Normalizer();
    Normalizer colorN = colorAttr ? Normalizer(*colorAttr, style.color.range) : Normalizer();
    Normalizer opacityN = opacityAttr ? Normalizer(*opacityAttr, style.opacity.range) : Normalizer();
    const glm::vec3 constantColor = srgbToLinear(style.color.constant);
    glm::vec3 nanSrgb =
        style.color.nanColor.value_or(colormap && colormap->nanColor ? *colormap->nanColor : glm::vec3(0.5f));
    const glm::vec3 nanColor = srgbToLinear(nanSrgb);

    // Lab, Diverging and HSV interpolation cost microseconds per sample (cube roots, trig): such
    // maps are tabulated once at 4097 points (t = k / 4096) and interpolated linearly, within
    // 1e-5 of the exact colour where the map is smooth. Control points at multiples of 1/4096
    // are table points, so the kink of a diverging map at its white point t = 0.5 is exact.
    // RGB and Step maps are sampled exactly.
    std::vector<glm::vec3> table;
    if (colormap && colormap->space != ColorSpace::Rgb && colormap->space != ColorSpace::Step) {
        table.resize(4097);
        tbb::parallel_for(std::size_t(0), table.size(),
                          [&](std::size_t i) { table[i] = colormap->sampleSrgb(float(i) / float(table.size() - 1)); });
    }
    auto sample = [&](float t) {
        if (table.empty()) return colormap->sampleSrgb(t);
        float x = t * float(table.size() - 1);
        std::size_t i = std::min(std::size_t(x), table.size() - 2);
        return glm::mix(table[i], table[i + 1], x - float(i));
    };
    // Vertices are independent.
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        float radius = style.radius.constant;
        if (radiusAttr) {
            float t = radiusN(radiusAttr->values[i]);
            radius = glm::mix(style.radius.radiusLo, style.radius.radiusHi, std::isnan(t) ? 0.0f : t);
        }
        glm::vec3 rgb = constantColor;
        if (colorAttr) {
            float t = colorN(colorAttr->values[i]);
            rgb = std::isnan(t) ? nanColor : srgbToLinear(sample(t));
        }
        float alpha = style.opacity.constant;
        if (opacityAttr) {
            float t = opacityN(opacityAttr->values[i]);
            alpha = evaluateTransferFunction(*opacityPoints, std::isnan(t) ? 0.0f : t);
        }
        out.positionRadius[i] = glm::vec4(lines.positions[i], radius);
        out.color[i] = glm::vec4(rgb, alpha);
    });
    if (style.color.direction) directionColors(lines, out.color);
    for (std::size_t i = 0; i < n; ++i) {
        out.bounds.extend(lines.positions[i], out.positionRadius[i].w);
        out.maxRadius = std::max(out.maxRadius, out.positionRadius[i].w);
    }

    out.segmentVertices.reserve(2 * lines.segmentCount());
    for (std::size_t p = 0; p < lines.polylineCount(); ++p) {
        std::uint32_t begin = lines.offsets[p], end = lines.offsets[p + 1];
        for (std::uint32_t v = begin; v < end; ++v) out.polylineId[v] = std::uint32_t(p);
        out.flags[begin] |= FirstOfPolyline;
        out.flags[end - 1] |= LastOfPolyline;
        for (std::uint32_t v = begin; v + 1 < end; ++v) {
            out.segmentVertices.push_back(v);
            out.segmentVertices.push_back(v + 1);
        }
    }
    return out;
}

bool anyTranslucent(const StyledLines& lines) {
    for (const glm::vec4& c : lines.color)
        if (c.w < 1.0f) return true;
    return false;
}

}  // namespace tc
