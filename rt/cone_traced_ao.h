#pragma once
// render.ao.method "cone_traced" on the CPU: the density volume of core/voxel_density.h with the
// mip pyramid of gl/density_volume.cpp (shaders/density_mip.comp) and the cone marching of
// shaders/cone_tracing.glsl, ported line by line so the ray-traced picture matches the GL one.
// Sampling reproduces a GL_LINEAR_MIPMAP_LINEAR 3D texture with CLAMP_TO_BORDER (border 0):
// trilinear within a level, linear between the two levels around the LOD. Keep in lock-step with
// the shader (its header comment explains the occlusion model and the self-occlusion handling).
#include <glm/glm.hpp>
#include <vector>

#include "core/mip_pyramid.h"
#include "core/region.h"
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

    int levels() const { return m_mip.levels(); }
    glm::ivec3 levelSize(int level) const { return m_mip.levelSize(level); }
    const glm::ivec3& size() const { return m_mip.size(); }
    const glm::vec3& origin() const { return m_origin; }
    float voxelSize() const { return m_voxelSize; }
    // GL textureLod(sampler3D, uvw, lod) with the filters above; uvw in [0, 1]^3 over the grid.
    float textureLod(const glm::vec3& uvw, float lod) const { return m_mip.textureLod(uvw, lod); }
    // One level, trilinear between texel centres, 0 outside (the border colour).
    float sampleLevel(const glm::vec3& uvw, int level) const { return m_mip.sampleLevel(uvw, level); }
    // Texel (x, y, z) of `level`, 0 outside the level (the border colour).
    float texel(int level, int x, int y, int z) const { return m_mip.texel(level, x, y, z); }
    std::size_t bytes() const { return m_mip.bytes(); }

private:
    MipPyramid<float> m_mip;
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
};

// ConeOwnTube of shaders/cone_tracing.glsl: the shaded tube, excluded from the density reads.
struct ConeOwnTube {
    glm::vec3 origin{0.0f};           // a point on the axis, world
    glm::vec3 dir{0.0f, 0.0f, 1.0f};  // unit axis
    float density = 0.0f;             // deposit per voxel of axis length; 0: none
};
// coneOwnTube of shaders/cone_tracing.glsl: the rounded cone a -> b (xyz, radius w).
ConeOwnTube coneOwnTube(const glm::vec4& a, const glm::vec4& b, float alphaA, float alphaB, float voxelSize);

// traceOcclusionCone of shaders/cone_tracing.glsl: occlusion in [0, 1] of one cone.
float traceOcclusionCone(const DensityPyramid& volume, const ConeTracingParams& params, glm::vec3 apex, glm::vec3 dir,
                         float tanHalfAperture, const ConeOwnTube& own = {});

// coneTracedTubeOcclusion of shaders/cone_tracing.glsl: AO factor (1 = unoccluded) at `position`
// on the surface of `own` (default: no own tube, coneTracedOcclusion).
float coneTracedOcclusion(const DensityPyramid& volume, const ConeTracingParams& params, glm::vec3 position,
                          glm::vec3 normal, const ConeOwnTube& own = {});

class ConeTracedAo final : public AoEstimator {
public:
    // Voxelizes `lines` at spec.resolution and builds the pyramid (once per dataset), with the
    // parameters gl::AmbientOcclusion::create derives from `spec`. `lines` must outlive it
    // (visibility excludes the shaded segment's own tube). `region`: data bounds and density
    // reduction of data-parallel rendering (core/voxel_density.h buildLineDensity).
    ConeTracedAo(const AoSpec& spec, const StyledLines& lines, const RegionSetup& region = {});
    float visibility(const glm::vec3& p, const glm::vec3& n, std::uint32_t pixel, std::uint32_t segment) const override;
    nlohmann::json describe() const override;

    const DensityPyramid& volume() const { return m_volume; }
    const ConeTracingParams& params() const { return m_params; }

private:
    ConeTracingParams m_params;
    const StyledLines* m_lines = nullptr;
    double m_buildMs = 0;  // before m_volume: set while m_volume is built
    DensityPyramid m_volume;
};

}  // namespace tc::rt
