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
#include "rt/ao_estimator.h"

namespace tc::rt {

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
