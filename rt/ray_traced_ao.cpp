#include "rt/ray_traced_ao.h"

#include <cmath>
#include <glm/gtc/constants.hpp>
#include <limits>

#include "rt/cone_traced_ao.h"
#include "rt/embree_lines.h"

namespace tc::rt {

RayTracedAo::RayTracedAo(const AoSpec& spec, const StyledLines& lines, const EmbreeLines& embree)
    : m_lines(lines), m_embree(embree) {
    m_strata = std::max(1, int(std::lround(std::sqrt(double(spec.samples)))));
    m_distance = spec.distance * glm::length(lines.bounds.extent());
    m_strength = spec.strength;
    // Off the surface by a small fraction of the radius: far enough that the ray does not re-hit
    // its own tube from rounding, close enough not to skip a touching neighbour.
    m_offset = 1e-3f * std::max(lines.maxRadius, 1e-12f);
}

float RayTracedAo::visibility(const glm::vec3& p, const glm::vec3& n, std::uint32_t pixel, std::uint32_t) const {
    const glm::vec3 origin = p + (m_offset + 1e-6f * glm::length(p)) * n;
    float blocked = 0.0f;
    const int m = m_strata;
    traceHemisphereRays(
        m_embree.scene(), origin, n, pixel, m, m_distance, [&](const RTCRayHit& rh, const glm::vec3& dir) {
            const std::uint32_t v0 = m_lines.segmentVertices[2 * rh.hit.primID];
            const std::uint32_t v1 = m_lines.segmentVertices[2 * rh.hit.primID + 1];
            const glm::vec3 x0(m_lines.positionRadius[v0]), x1(m_lines.positionRadius[v1]);
            const glm::vec3 q = origin + rh.ray.tfar * dir;
            const float len2 = glm::dot(x1 - x0, x1 - x0);
            const float u = len2 > 0.0f ? glm::clamp(glm::dot(q - x0, x1 - x0) / len2, 0.0f, 1.0f) : 0.0f;
            blocked += glm::mix(m_lines.color[v0].w, m_lines.color[v1].w, u);
        });
    const float visible = 1.0f - blocked / float(m * m);
    return std::pow(std::max(visible, 0.0f), m_strength);
}

nlohmann::json RayTracedAo::describe() const {
    return {{"method", "ray traced hemisphere (Embree)"},
            {"samples", m_strata * m_strata},
            {"distance_world", m_distance},
            {"strength", m_strength}};
}

std::unique_ptr<AoEstimator> makeAoEstimator(const AoSpec& spec, const StyledLines& lines, const EmbreeLines& embree,
                                             const RegionSetup& region) {
    if (spec.method == AoSpec::Method::RayTraced) return std::make_unique<RayTracedAo>(spec, lines, embree);
    return std::make_unique<ConeTracedAo>(spec, lines, region);
}

}  // namespace tc::rt
