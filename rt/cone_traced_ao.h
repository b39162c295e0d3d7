#pragma once
// render.ao.method "cone_traced" on the CPU: the density volume of core/voxel_density.h with the
// mip pyramid of gl/density_volume.cpp (shaders/density_mip.comp) and the cone marching of
// shaders/cone_tracing.glsl, ported line by line so the ray-traced picture matches the GL one.
// Sampling reproduces a GL_LINEAR_MIPMAP_LINEAR 3D texture with CLAMP_TO_BORDER (border 0):
// trilinear within a level, linear between the two levels around the LOD. Keep in lock-step with
// the shader (its header comment explains the occlusion model and the self-occlusion handling).
#include <vector>

#include <glm/glm.hpp>

#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/voxel_density.h"
#include "rt/ao_estimator.h"

namespace tc::rt {

// The density pyramid: level 0 is the voxelized grid, level L + 1 the area-weighted average of
// level L with max(1, n / 2) texels per axis (the taps of shaders/density_mip.comp).
class DensityPyramid {
public:
    explicit DensityPyramid(DensityGrid grid);

    int levels() const { return int(m_levels.size()); }
    glm::ivec3 levelSize(int level) const { return m_sizes[std::size_t(level)]; }
    const glm::ivec3& size() const { return m_sizes[0]; }
    const glm::vec3& origin() const { return m_origin; }
    float voxelSize() const { return m_voxelSize; }
    // GL textureLod(sampler3D, uvw, lod) with the filters above; uvw in [0, 1]^3 over the grid.
    float textureLod(const glm::vec3& uvw, float lod) const;
    // One level, trilinear between texel centres, 0 outside (the border colour).
    float sampleLevel(const glm::vec3& uvw, int level) const;
    std::size_t bytes() const;

private:
    float fetch(int level, int x, int y, int z) const;
    std::vector<std::vector<float>> m_levels;
    std::vector<glm::ivec3> m_sizes;
    glm::vec3 m_origin{0.0f};
    float m_voxelSize = 1.0f;
};

// Parameters of one cone tracing evaluation, as gl::AmbientOcclusion sets its uniforms.
struct ConeTracingParams {
    int cones = 3;
    float apertureRad = 0.0f;  // full apex angle
    float maxDistance = 0.0f;  // world units
    float strength = 1.0f;
    float startOffset = 0.0f;  // world units
    float ownArea = 0.0f;      // uConeOwnArea: pi maxRadius^2 / voxelSize^2
};

// coneTracedOcclusion of shaders/cone_tracing.glsl: AO factor (1 = unoccluded) at `position`.
float coneTracedOcclusion(const DensityPyramid& volume, const ConeTracingParams& params, glm::vec3 position,
                          glm::vec3 normal);

class ConeTracedAo final : public AoEstimator {
public:
    // Voxelizes `lines` at spec.resolution and builds the pyramid (once per dataset), with the
    // parameters gl::AmbientOcclusion::create derives from `spec`.
    ConeTracedAo(const AoSpec& spec, const StyledLines& lines);
    float visibility(const glm::vec3& p, const glm::vec3& n, std::uint32_t pixel) const override;
    nlohmann::json describe() const override;

    const DensityPyramid& volume() const { return m_volume; }
    const ConeTracingParams& params() const { return m_params; }

private:
    ConeTracingParams m_params;
    double m_buildMs = 0;  // before m_volume: set while m_volume is built
    DensityPyramid m_volume;
};

}  // namespace tc::rt
