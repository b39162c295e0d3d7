#pragma once
// render.ao.method "ray_traced": ambient occlusion by hemisphere rays against the same Embree
// tubes the image is traced from. m x m stratified, cosine-weighted directions around the normal
// facing the viewer (m = round(sqrt(render.ao.samples)), at least 1), jittered within their strata
// by a hash of (pixel, sample): deterministic per pixel, independent of threads and tiles. Each ray
// starts just off the surface and reaches render.ao.distance (fraction of the bounding-box
// diagonal, as the cones). A ray that hits a tube is blocked by that tube's opacity at the hit
// (the vertex alpha, interpolated), so transparent tubes occlude in proportion, as they do in the
// density volume. AO = (1 - mean blocked)^strength: cosine-weighted sampling makes the plain mean
// the cosine-weighted hemisphere integral.
#include <embree3/rtcore.h>

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include "core/tangent_frame.h"
#include "rt/ao_estimator.h"
#include "rt/primary_rays.h"

namespace tc::rt {

namespace detail {
// PCG-style integer hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering"): cheap and
// well mixed, so neighbouring pixels get unrelated jitter.
inline std::uint32_t pcgHash(std::uint32_t v) {
    std::uint32_t state = v * 747796405u + 2891336453u;
    std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
inline float unitFloat(std::uint32_t h) {
    return float(h >> 8) * (1.0f / 16777216.0f);
}
}  // namespace detail

// The hemisphere rays of "ray_traced" AO (lines and particles): m x m stratified cosine-weighted
// directions around the unit normal n (Malley's method), jittered by a hash of `pixel`, from
// `origin` to `distance` in `scene`. Calls onHit(rayHit, dir) for every ray that hits something.
template <class OnHit>
void traceHemisphereRays(RTCScene scene, const glm::vec3& origin, const glm::vec3& n, std::uint32_t pixel, int m,
                         float distance, OnHit&& onHit) {
    glm::vec3 t, b;
    tangentFrame(n, t, b);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::uint32_t seed = detail::pcgHash(pixel);
    for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
            seed = detail::pcgHash(seed);
            const float u1 = (float(i) + detail::unitFloat(seed)) / float(m);
            seed = detail::pcgHash(seed);
            const float u2 = (float(j) + detail::unitFloat(seed)) / float(m);
            // Cosine-weighted: uniform on the disk, projected up.
            const float r = std::sqrt(u1), phi = glm::two_pi<float>() * u2;
            const glm::vec3 dir = glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b +
                                                 std::sqrt(std::max(0.0f, 1.0f - u1)) * n);
            RTCRayHit rh = makeRayHit(Ray{origin, dir}, 0.0f);
            rh.ray.tfar = distance;
            rtcIntersect1(scene, &context, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) onHit(rh, dir);
        }
}

class RayTracedAo final : public AoEstimator {
public:
    RayTracedAo(const AoSpec& spec, const StyledLines& lines, const EmbreeLines& embree);
    float visibility(const glm::vec3& p, const glm::vec3& n, std::uint32_t pixel, std::uint32_t segment) const override;
    nlohmann::json describe() const override;

private:
    const StyledLines& m_lines;
    const EmbreeLines& m_embree;
    int m_strata = 4;  // per axis
    float m_distance = 0;
    float m_strength = 1;
    float m_offset = 0;  // world units off the surface
};

}  // namespace tc::rt
