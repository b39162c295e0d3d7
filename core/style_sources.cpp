#include "core/style_sources.h"

#include <sstream>

namespace tc {
namespace {

std::string number(float v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string radiusSource(const RadiusSpec& r, const ParticleSet* first) {
    if (!r.attribute.empty())
        return "radius: attribute \"" + r.attribute + "\" mapped to [" + number(r.radiusLo) + ", " +
               number(r.radiusHi) + "] from the scene";
    if (r.fromScene) return "radius: constant " + number(r.constant) + " from the scene";
    if (first && !first->radii.empty()) {
        if (first->radiiFrom == Provenance::Elements) {
            std::string list;
            for (const auto& [element, radius] : first->elementRadii)
                list += (list.empty() ? "" : ", ") + element + " " + number(radius);
            return "radius: element radii (" + list + ")";
        }
        return "radius: per-particle radii from the file";
    }
    return "radius: constant " + number(r.constant) + " (default)";
}

std::string colorSource(const ColorSpec& c, const ParticleSet* first) {
    if (c.direction) return "colour: direction-encoded (|dx|, |dy|, |dz|) from the scene";
    if (!c.attribute.empty())
        return "colour: attribute \"" + c.attribute + "\" through " + c.colormap + " from the scene";
    std::ostringstream
        rgbText;  // a stream, not "[" + std::string: GCC 12's -Wrestrict misfires on that (GCC bug 105329)
    rgbText << '[' << c.constant.x << ", " << c.constant.y << ", " << c.constant.z << ']';
    const std::string rgb = rgbText.str();
    if (c.fromScene) return "colour: constant " + rgb + " from the scene";
    if (first && !first->colors.empty())
        return first->colorsFrom == Provenance::Elements ? "colour: element colours (CPK)"
                                                         : "colour: per-particle colours from the file";
    return "colour: constant " + rgb + " (default)";
}

std::string opacitySource(const OpacitySpec& o) {
    if (!o.attribute.empty())
        return "opacity: attribute \"" + o.attribute + "\" through a transfer function from the scene";
    return "opacity: " + number(o.constant) + (o.fromScene ? " from the scene" : " (default)");
}

}  // namespace

std::vector<std::string> styleSources(const StyleSpec& style, const ParticleData* particles) {
    const ParticleSet* first = particles && !particles->frames.empty() ? &particles->frames.front() : nullptr;
    return {radiusSource(style.radius, first), colorSource(style.color, first), opacitySource(style.opacity)};
}

}  // namespace tc
