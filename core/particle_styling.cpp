#include "core/particle_styling.h"

#include <algorithm>

#include "core/color.h"
#include "core/error.h"
#include "core/styling.h"

namespace tc {

StyledParticles styleParticles(const ParticleSet& particles, const StyleSpec& style, const std::string& sceneFile) {
    particles.checkConsistent();
    if (style.color.direction)
        throw InputError((sceneFile.empty() ? std::string("scene") : sceneFile) +
                         ": style.color: \"direction\" colours lines by their direction; particles have none");
    StyledParticles out;
    const std::size_t n = particles.size();
    if (n == 0) return out;

    // The mappings are the line styling's (core/styling.cpp), applied to the particles as the
    // vertices of one polyline: one implementation of ranges, colormaps, transfer functions and
    // NaN rules for lines and particles, and the same error messages.
    LineSet asLine;
    asLine.positions = particles.positions;
    asLine.offsets = {0u, std::uint32_t(n)};
    asLine.attributes = particles.attributes;
    asLine.bounds = particles.bounds;
    StyledLines styled = styleLines(asLine, style, sceneFile);

    // Precedence (docs/scene-spec.md): what the scene states wins; radii and colours the data
    // carries or implies (element radii and colours) win over the defaults.
    const bool dataRadii = !particles.radii.empty() && !style.radius.fromScene && style.radius.attribute.empty();
    const bool dataColors = !particles.colors.empty() && !style.color.fromScene && style.color.attribute.empty();
    out.centerRadius = std::move(styled.positionRadius);
    out.color = std::move(styled.color);
    out.id.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        out.id[i] = std::uint32_t(i);
        if (dataRadii) out.centerRadius[i].w = particles.radii[i];
        if (dataColors) {
            const glm::vec4& c = particles.colors[i];
            out.color[i] = glm::vec4(srgbToLinear(glm::vec3(c)), out.color[i].w * c.w);
        }
        // Radii from files can be zero or negative (a malformed column is caught by the reader;
        // an element without a radius gets a default there); a sphere needs r > 0.
        out.centerRadius[i].w = std::max(out.centerRadius[i].w, 1e-12f);
        out.bounds.extend(glm::vec3(out.centerRadius[i]), out.centerRadius[i].w);
        out.maxRadius = std::max(out.maxRadius, out.centerRadius[i].w);
    }
    return out;
}

std::optional<ValueRange> colorMappingRange(const ParticleSet& particles, const StyleSpec& style,
                                            const std::string& sceneFile) {
    if (style.color.attribute.empty() || particles.size() == 0) return std::nullopt;
    LineSet asLine;  // as styleParticles sees them
    asLine.positions = particles.positions;
    asLine.offsets = {0u, std::uint32_t(particles.size())};
    asLine.attributes = particles.attributes;
    asLine.bounds = particles.bounds;
    return colorMappingRange(asLine, style, sceneFile);
}

StyledParticles particlesFromLineVertices(const StyledLines& lines) {
    StyledParticles out;
    out.centerRadius = lines.positionRadius;
    out.color = lines.color;
    out.id = lines.polylineId;
    out.bounds = lines.bounds;
    out.maxRadius = lines.maxRadius;
    return out;
}

}  // namespace tc
