#include "core/colormap.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "core/colormap_tables.h"
#include "core/error.h"

namespace tc {

const char* colorSpaceName(ColorSpace space) {
    switch (space) {
        case ColorSpace::Rgb:
            return "RGB";
        case ColorSpace::Lab:
            return "Lab";
        case ColorSpace::Diverging:
            return "Diverging";
        case ColorSpace::Hsv:
            return "HSV";
        case ColorSpace::Step:
            return "Step";
    }
    return "RGB";
}

// The conversions below follow vtkMath (RGBToXYZ, XYZToLab, LabToXYZ, XYZToRGB) constant for
// constant rather than a colour library's: ParaView presets are authored against exactly these,
// and matching them is what makes an imported preset look the same here. Computed in double
// because the cube roots near the black point lose digits in float.
namespace {

constexpr double kRefX = 0.9505, kRefY = 1.000, kRefZ = 1.089;  // D65, as vtkMath

double decodeSrgb(double c) {
    return c > 0.04045 ? std::pow((c + 0.055) / 1.055, 2.4) : c / 12.92;
}
double encodeSrgb(double c) {
    return c > 0.0031308 ? 1.055 * std::pow(c, 1 / 2.4) - 0.055 : 12.92 * c;
}
double labF(double v) {
    return v > 0.008856 ? std::cbrt(v) : 7.787 * v + 16.0 / 116.0;
}
double labFInverse(double v) {
    return v * v * v > 0.008856 ? v * v * v : (v - 16.0 / 116.0) / 7.787;
}

}  // namespace

glm::vec3 srgbToLab(const glm::vec3& srgb) {
    double r = decodeSrgb(srgb.x), g = decodeSrgb(srgb.y), b = decodeSrgb(srgb.z);
    double x = r * 0.4124 + g * 0.3576 + b * 0.1805;
    double y = r * 0.2126 + g * 0.7152 + b * 0.0722;
    double z = r * 0.0193 + g * 0.1192 + b * 0.9505;
    double fx = labF(x / kRefX), fy = labF(y / kRefY), fz = labF(z / kRefZ);
    return {float(116 * fy - 16), float(500 * (fx - fy)), float(200 * (fy - fz))};
}

glm::vec3 labToSrgb(const glm::vec3& lab) {
    double fy = (double(lab.x) + 16) / 116, fx = double(lab.y) / 500 + fy, fz = fy - double(lab.z) / 200;
    double x = kRefX * labFInverse(fx), y = kRefY * labFInverse(fy), z = kRefZ * labFInverse(fz);
    double r = encodeSrgb(x * 3.2406 + y * -1.5372 + z * -0.4986);
    double g = encodeSrgb(x * -0.9689 + y * 1.8758 + z * 0.0415);
    double b = encodeSrgb(x * 0.0557 + y * -0.2040 + z * 1.0570);
    // Out of gamut: VTK scales the brightest component down to 1, then clips negatives.
    double m = std::max({r, g, b});
    if (m > 1) r /= m, g /= m, b /= m;
    return {float(std::max(r, 0.0)), float(std::max(g, 0.0)), float(std::max(b, 0.0))};
}

glm::vec3 srgbToHsv(const glm::vec3& c) {
    float hi = std::max({c.x, c.y, c.z}), lo = std::min({c.x, c.y, c.z});
    float s = hi > 0 ? (hi - lo) / hi : 0.0f, h = 0;
    if (s > 0) {
        float d = hi - lo;
        if (c.x == hi)
            h = (c.y - c.z) / d / 6;
        else if (c.y == hi)
            h = 1.0f / 3 + (c.z - c.x) / d / 6;
        else
            h = 2.0f / 3 + (c.x - c.y) / d / 6;
        if (h < 0) h += 1;
    }
    return {h, s, hi};
}

glm::vec3 hsvToSrgb(const glm::vec3& hsv) {
    float h = hsv.x - std::floor(hsv.x);
    // Fully saturated hue, then desaturated and scaled by the value.
    glm::vec3 hue =
        glm::clamp(glm::vec3(std::abs(h * 6 - 3) - 1, 2 - std::abs(h * 6 - 2), 2 - std::abs(h * 6 - 4)), 0.0f, 1.0f);
    return hsv.z * glm::mix(glm::vec3(1.0f), hue, hsv.y);
}

namespace {

// Moreland, "Diverging Color Maps for Scientific Visualization" (ISVC 2009), Sect. 4-5: Msh is
// Lab in spherical coordinates (M = |Lab|, s = angle from the L axis, h = hue angle).
glm::dvec3 labToMsh(const glm::dvec3& lab) {
    double m = glm::length(lab);
    double s = m > 0.001 ? std::acos(lab.x / m) : 0.0;
    double h = s > 0.001 ? std::atan2(lab.z, lab.y) : 0.0;
    return {m, s, h};
}

glm::dvec3 mshToLab(const glm::dvec3& msh) {
    return {msh.x * std::cos(msh.y), msh.x * std::sin(msh.y) * std::cos(msh.z),
            msh.x * std::sin(msh.y) * std::sin(msh.z)};
}

double angleDifference(double a, double b) {
    constexpr double pi = std::numbers::pi;
    double d = std::fmod(std::abs(a - b), 2 * pi);
    return d > pi ? 2 * pi - d : d;
}

// The hue an unsaturated colour should take when interpolated toward a saturated one
// (Moreland 2009, Sect. 5, "AdjustHue"), so the interpolation does not swing through hues.
double adjustHue(const glm::dvec3& saturated, double unsaturatedM) {
    if (saturated.x >= unsaturatedM - 0.1) return saturated.z;
    double spin = saturated.y * std::sqrt(unsaturatedM * unsaturatedM - saturated.x * saturated.x) /
                  (saturated.x * std::sin(saturated.y));
    return saturated.z > -0.3 * std::numbers::pi ? saturated.z + spin : saturated.z - spin;
}

glm::vec3 interpolateDiverging(const glm::vec3& a, const glm::vec3& b, double s) {
    glm::dvec3 m1 = labToMsh(glm::dvec3(srgbToLab(a))), m2 = labToMsh(glm::dvec3(srgbToLab(b)));
    // Two saturated, clearly different hues: pass through white (the diverging midpoint) at
    // M = max(M1, M2, 88), Moreland's choice that gives the familiar (221, 221, 221) centre.
    if (m1.y > 0.05 && m2.y > 0.05 && angleDifference(m1.z, m2.z) > 0.33 * std::numbers::pi) {
        double mid = std::max({m1.x, m2.x, 88.0});
        if (s < 0.5) {
            m2 = {mid, 0, 0};
            s *= 2;
        } else {
            m1 = {mid, 0, 0};
            s = 2 * s - 1;
        }
    }
    if (m1.y < 0.05 && m2.y > 0.05)
        m1.z = adjustHue(m2, m1.x);
    else if (m2.y < 0.05 && m1.y > 0.05)
        m2.z = adjustHue(m1, m2.x);
    return labToSrgb(glm::vec3(mshToLab(glm::mix(m1, m2, s))));
}

}  // namespace

glm::vec3 interpolateSrgb(ColorSpace space, const glm::vec3& a, const glm::vec3& b, float s) {
    switch (space) {
        case ColorSpace::Rgb:
            return glm::mix(a, b, s);
        case ColorSpace::Lab:
            return labToSrgb(glm::mix(srgbToLab(a), srgbToLab(b), s));
        case ColorSpace::Diverging:
            return interpolateDiverging(a, b, s);
        case ColorSpace::Hsv: {
            glm::vec3 h1 = srgbToHsv(a), h2 = srgbToHsv(b);
            if (std::abs(h1.x - h2.x) > 0.5f) (h1.x > h2.x ? h1.x : h2.x) -= 1.0f;
            glm::vec3 h = glm::mix(h1, h2, s);
            if (h.x < 0) h.x += 1;
            return hsvToSrgb(h);
        }
        case ColorSpace::Step:
            return s > 0 ? b : a;
    }
    return glm::mix(a, b, s);
}

glm::vec3 Colormap::sampleSrgb(float x) const {
    if (std::isnan(x)) return nanColor.value_or(glm::vec3(0.5f));
    x = std::clamp(x, 0.0f, 1.0f);
    auto it = std::upper_bound(t.begin(), t.end(), x);
    if (it == t.begin()) return srgb.front();
    if (it == t.end()) return srgb.back();
    std::size_t i = std::size_t(it - t.begin());
    float s = (x - t[i - 1]) / std::max(t[i] - t[i - 1], 1e-12f);
    return interpolateSrgb(space, srgb[i - 1], srgb[i], s);
}

void validateColormap(const Colormap& map, const std::string& source) {
    auto fail = [&](const std::string& what) { throw InputError(source + ": " + what); };
    if (map.t.size() < 2 || map.t.size() != map.srgb.size())
        fail("a colormap needs at least 2 control points, got " + std::to_string(map.srgb.size()));
    if (map.t.front() != 0.0f || map.t.back() != 1.0f) fail("control points must span t = 0 .. 1");
    for (std::size_t i = 0; i < map.t.size(); ++i) {
        if (!std::isfinite(map.t[i]) || (i > 0 && map.t[i] < map.t[i - 1]))
            fail("control point " + std::to_string(i) + ": positions must be finite and ascending");
        const glm::vec3& c = map.srgb[i];
        if (!(c.x >= 0 && c.x <= 1 && c.y >= 0 && c.y <= 1 && c.z >= 0 && c.z <= 1))
            fail("control point " + std::to_string(i) + ": colour components must be in [0, 1]");
    }
    for (std::size_t i = 0; i < map.opacity.size(); ++i) {
        const glm::vec2& p = map.opacity[i];
        if (!(p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1) || (i > 0 && p.x < map.opacity[i - 1].x))
            fail("opacity point " + std::to_string(i) + ": expected t ascending in [0, 1] and opacity in [0, 1]");
    }
}

namespace {

Colormap fromTable(const std::string& name, const float (&table)[256][3]) {
    Colormap m;
    m.name = name;
    for (int i = 0; i < 256; ++i) {
        m.t.push_back(float(i) / 255.0f);
        m.srgb.push_back({table[i][0], table[i][1], table[i][2]});
    }
    m.t.back() = 1.0f;
    return m;
}

const std::map<std::string, Colormap>& table() {
    static const std::map<std::string, Colormap> maps = [] {
        std::map<std::string, Colormap> m;
        auto add = [&](Colormap c) { m.emplace(c.name, std::move(c)); };
        add(fromTable("viridis", colormap_tables::Viridis));
        add(fromTable("magma", colormap_tables::Magma));
        add(fromTable("inferno", colormap_tables::Inferno));
        add(fromTable("plasma", colormap_tables::Plasma));
        add(fromTable("turbo", colormap_tables::Turbo));
        // Moreland 2009, Table 1 / Fig. 6: the cool (59, 76, 192) and warm (180, 4, 38) endpoints;
        // everything in between comes from the Msh interpolation, as in ParaView's "Cool to Warm".
        Colormap coolWarm;
        coolWarm.name = "cool_warm";
        coolWarm.space = ColorSpace::Diverging;
        coolWarm.t = {0.0f, 1.0f};
        coolWarm.srgb = {glm::vec3(59, 76, 192) / 255.0f, glm::vec3(180, 4, 38) / 255.0f};
        add(coolWarm);
        Colormap gray;
        gray.name = "grayscale";
        gray.t = {0.0f, 1.0f};
        gray.srgb = {glm::vec3(0.0f), glm::vec3(1.0f)};
        add(gray);
        return m;
    }();
    return maps;
}

}  // namespace

std::vector<std::string> builtinColormapNames() {
    std::vector<std::string> names;
    for (const auto& [name, map] : table()) names.push_back(name);
    return names;
}

bool isBuiltinColormap(const std::string& name) {
    return table().count(name) > 0;
}

const Colormap& builtinColormap(const std::string& name) {
    auto it = table().find(name);
    if (it == table().end()) {
        std::string known;
        for (const auto& n : builtinColormapNames()) known += (known.empty() ? "" : ", ") + n;
        throw InputError("unknown colormap \"" + name + "\" (built-in: " + known + ")");
    }
    return it->second;
}

}  // namespace tc
