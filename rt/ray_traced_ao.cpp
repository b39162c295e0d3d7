#include "rt/ray_traced_ao.h"

#include <cmath>
#include <limits>

#include <glm/gtc/constants.hpp>

#include "rt/cone_traced_ao.h"
#include "rt/embree_lines.h"

namespace tc::rt {
namespace {

// PCG-style integer hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering"): cheap and
// well mixed, so neighbouring pixels get unrelated jitter.
std::uint32_t pcgHash(std::uint32_t v) {
    std::uint32_t state = v * 747796405u + 2891336453u;
    std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
float unitFloat(std::uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }

}  // namespace

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
    glm::vec3 t, b;
    {
        // Duff et al. 2017 tangent frame (as the cone tracer).
        const float s = n.z >= 0.0f ? 1.0f : -1.0f;
        const float a = -1.0f / (s + n.z);
        const float c = n.x * n.y * a;
        t = glm::vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
        b = glm::vec3(c, s + n.y * n.y * a, -n.y);
    }
    const glm::vec3 origin = p + (m_offset + 1e-6f * glm::length(p)) * n;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    float blocked = 0.0f;
    const int m = m_strata;
    std::uint32_t seed = pcgHash(pixel);
    for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
            seed = pcgHash(seed);
            const float u1 = (float(i) + unitFloat(seed)) / float(m);
            seed = pcgHash(seed);
            const float u2 = (float(j) + unitFloat(seed)) / float(m);
            // Cosine-weighted (Malley's method): uniform on the disk, projected up.
            const float r = std::sqrt(u1), phi = glm::two_pi<float>() * u2;
            const glm::vec3 dir =
                glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1.0f - u1)) * n);
            RTCRayHit rh;
            rh.ray.org_x = origin.x, rh.ray.org_y = origin.y, rh.ray.org_z = origin.z;
            rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
            rh.ray.tnear = 0.0f;
            rh.ray.tfar = m_distance;
            rh.ray.time = 0.0f;
            rh.ray.mask = 0xFFFFFFFFu;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(m_embree.scene(), &context, &rh);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
            const std::uint32_t v0 = m_lines.segmentVertices[2 * rh.hit.primID];
            const std::uint32_t v1 = m_lines.segmentVertices[2 * rh.hit.primID + 1];
            const glm::vec3 x0(m_lines.positionRadius[v0]), x1(m_lines.positionRadius[v1]);
            const glm::vec3 q = origin + rh.ray.tfar * dir;
            const float len2 = glm::dot(x1 - x0, x1 - x0);
            const float u = len2 > 0.0f ? glm::clamp(glm::dot(q - x0, x1 - x0) / len2, 0.0f, 1.0f) : 0.0f;
            blocked += glm::mix(m_lines.color[v0].w, m_lines.color[v1].w, u);
        }
    const float visible = 1.0f - blocked / float(m * m);
    return std::pow(std::max(visible, 0.0f), m_strength);
}

nlohmann::json RayTracedAo::describe() const {
    return {{"method", "ray traced hemisphere (Embree)"},
            {"samples", m_strata * m_strata},
            {"distance_world", m_distance},
            {"strength", m_strength}};
}

std::unique_ptr<AoEstimator> makeAoEstimator(const AoSpec& spec, const StyledLines& lines, const EmbreeLines& embree) {
    if (spec.method == AoSpec::Method::RayTraced) return std::make_unique<RayTracedAo>(spec, lines, embree);
    return std::make_unique<ConeTracedAo>(spec, lines);
}

}  // namespace tc::rt
