#include "core/styling.h"

#include <algorithm>
#include <cmath>

#include "core/color.h"
#include "core/colormap.h"
#include "core/error.h"

namespace tc {

float evaluateTransferFunction(const std::vector<glm::vec2>& points, float t) {
    if (points.empty()) return 1.0f;
    if (t <= points.front().x) return points.front().y;
    for (std::size_t i = 1; i < points.size(); ++i)
        if (t <= points[i].x) {
            float w = points[i].x - points[i - 1].x;
            return w > 0 ? glm::mix(points[i - 1].y, points[i].y, (t - points[i - 1].x) / w) : points[i].y;
        }
    return points.back().y;
}

namespace {

const Attribute& requireAttribute(const LineSet& lines, const std::string& name, const std::string& sceneFile,
                                  const std::string& key) {
    if (const Attribute* a = lines.attribute(name)) return *a;
    std::string available;
    for (const auto& a : lines.attributes) available += (available.empty() ? "" : ", ") + a.name;
    throw InputError((sceneFile.empty() ? std::string("scene") : sceneFile) + ": " + key + ": the dataset has no attribute \"" +
                     name + "\" (available: " + (available.empty() ? "none" : available) + ")");
}

// Normalised attribute value in [0,1] for a range; NaN stays NaN.
struct Normalizer {
    float lo, scale;
    Normalizer(const Attribute& a, const RangeSpec& r) {
        lo = r.automatic ? a.min : r.lo;
        float hi = r.automatic ? a.max : r.hi;
        if (!std::isfinite(lo) || !std::isfinite(hi)) lo = hi = 0.0f;
        scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
    }
    float operator()(float v) const { return std::isnan(v) ? v : std::clamp((v - lo) * scale, 0.0f, 1.0f); }
};

}  // namespace

StyledLines styleLines(const LineSet& lines, const StyleSpec& style, const std::string& sceneFile) {
    StyledLines out;
    const std::size_t n = lines.vertexCount();
    out.positionRadius.resize(n);
    out.color.resize(n);
    out.polylineId.resize(n);
    out.flags.assign(n, 0u);

    const Attribute* radiusAttr = style.radius.attribute.empty() ? nullptr
        : &requireAttribute(lines, style.radius.attribute, sceneFile, "style.radius.attribute");
    const Attribute* colorAttr = style.color.attribute.empty() ? nullptr
        : &requireAttribute(lines, style.color.attribute, sceneFile, "style.color.attribute");
    const Attribute* opacityAttr = style.opacity.attribute.empty() ? nullptr
        : &requireAttribute(lines, style.opacity.attribute, sceneFile, "style.opacity.attribute");
    const Colormap* colormap = colorAttr ? &builtinColormap(style.color.colormap) : nullptr;
    Normalizer radiusN = radiusAttr ? Normalizer(*radiusAttr, style.radius.range) : Normalizer({}, {});
    Normalizer colorN = colorAttr ? Normalizer(*colorAttr, style.color.range) : Normalizer({}, {});
    Normalizer opacityN = opacityAttr ? Normalizer(*opacityAttr, style.opacity.range) : Normalizer({}, {});
    const glm::vec3 constantColor = srgbToLinear(style.color.constant);
    const glm::vec3 nanColor = srgbToLinear(glm::vec3(0.5f));

    for (std::size_t i = 0; i < n; ++i) {
        float radius = style.radius.constant;
        if (radiusAttr) {
            float t = radiusN(radiusAttr->values[i]);
            radius = glm::mix(style.radius.radiusLo, style.radius.radiusHi, std::isnan(t) ? 0.0f : t);
        }
        glm::vec3 rgb = constantColor;
        if (colorAttr) {
            float t = colorN(colorAttr->values[i]);
            rgb = std::isnan(t) ? nanColor : srgbToLinear(colormap->sampleSrgb(t));
        }
        float alpha = style.opacity.constant;
        if (opacityAttr) {
            float t = opacityN(opacityAttr->values[i]);
            alpha = evaluateTransferFunction(style.opacity.points, std::isnan(t) ? 0.0f : t);
        }
        out.positionRadius[i] = glm::vec4(lines.positions[i], radius);
        out.color[i] = glm::vec4(rgb, alpha);
        out.bounds.extend(lines.positions[i], radius);
        out.maxRadius = std::max(out.maxRadius, radius);
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

}  // namespace tc
