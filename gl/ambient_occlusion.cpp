#include "gl/ambient_occlusion.h"

#include <chrono>

#include <glm/gtc/constants.hpp>

#include "core/voxel_density.h"
#include "gl/line_geometry.h"

namespace tc::gl {

AmbientOcclusion AmbientOcclusion::create(const AoSpec& spec, const StyledLines& lines) {
    AmbientOcclusion ao;
    ao.m_spec = spec;
    auto t0 = std::chrono::steady_clock::now();
    DensityGrid grid = makeDensityGrid(lines.bounds, spec.resolution);
    voxelizeLines(lines, grid);
    auto t1 = std::chrono::steady_clock::now();
    ao.m_volume = DensityVolume::create(grid);
    glFinish();
    auto t2 = std::chrono::steady_clock::now();
    ao.m_voxelizeMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
    ao.m_uploadMs = std::chrono::duration<double, std::milli>(t2 - t1).count();
    ao.m_clampedSegments = grid.clampedSegments;
    ao.m_distance = spec.distance * glm::length(lines.bounds.extent());
    // A tube must not occlude itself. shaders/cone_tracing.glsl ("Self-occlusion") excludes it
    // per step: where a read's footprint may reach behind the tangent plane it takes the larger
    // of a read at a level that stays in front of the plane and the cone-level read minus a bound
    // on one tube of maxRadius (m_ownArea). The start offset only skips the sub-voxel steps at
    // the apex. Measured on an isolated straight tube (tests/gl/ambient_occlusion_test.cpp, grid
    // 64, radius 0.5 / 1 / 2 voxels): the former offset maxRadius + 2 voxels alone gave AO min
    // 0.93 / 0.82 / 0.70; 16 voxels (half the cone) alone still 0.99 / 0.97 / 0.91 and lost most
    // of the near field (7x7 bundle, centre crest AO 0.04 -> 0.44); with the exclusion AO is
    // exactly 1 for offsets 0, 1 voxel or maxRadius + 2 voxels, which differ by < 0.01 in the
    // bundle (centre crest mean 0.2325 / 0.2325 / 0.2260).
    ao.m_startOffset = grid.voxelSize;
    ao.m_ownArea = glm::pi<float>() * (lines.maxRadius / grid.voxelSize) * (lines.maxRadius / grid.voxelSize);
    return ao;
}

void AmbientOcclusion::apply(GLuint p) const {
    m_volume.bind();
    m_volume.setUniforms(p);
    glProgramUniform1i(p, uniformLocation(p, "uAoCones"), m_spec.cones);
    glProgramUniform1f(p, uniformLocation(p, "uAoAperture"), glm::radians(m_spec.apertureDeg));
    glProgramUniform1f(p, uniformLocation(p, "uAoDistance"), m_distance);
    glProgramUniform1f(p, uniformLocation(p, "uAoStrength"), m_spec.strength);
    glProgramUniform1f(p, uniformLocation(p, "uAoStartOffset"), m_startOffset);
    glProgramUniform1f(p, uniformLocation(p, "uConeOwnArea"), m_ownArea);
    if (m_lineCache) m_lineCache->bind();
}

void AmbientOcclusion::buildLineCache(const LineGeometry& geometry, const StyledLines& lines) {
    if (m_spec.cache != AoSpec::Cache::Precomputed) return;
    // One sample per kAoCacheSpacingVoxels of segment length, at least the two ends. The finest
    // read of the tracer is one voxel, but along a tube AO changes slowly (neighbours are mostly
    // parallel); on the 1M-segment tornado (segments ~1-2 voxels) 1 voxel gave 3.0 M samples,
    // 2 voxels 2.x M, and the test scenes' agreement with the exact tracer did not change
    // measurably (tests/gl/ambient_occlusion_test.cpp).
    constexpr float kAoCacheSpacingVoxels = 2.0f;
    m_lineCache = AoLineCache::build(geometry, lines, kAoCacheSpacingVoxels * m_volume.voxelSize(),
                                     [this](GLuint p) { apply(p); });
}

std::vector<std::string> AmbientOcclusion::lineDefines() const {
    std::vector<std::string> defines{"AMBIENT_OCCLUSION"};
    if (m_lineCache) {
        defines.push_back("AO_LINE_CACHE");
        defines.push_back(AoLineCache::define());
    }
    return defines;
}

nlohmann::json AmbientOcclusion::describe() const {
    const glm::ivec3 s = m_volume.size();
    return {{"method", "voxel cone tracing"},
            {"grid", {s.x, s.y, s.z}},
            {"voxel_size", m_volume.voxelSize()},
            {"levels", m_volume.levels()},
            {"cones", m_spec.cones},
            {"aperture_deg", m_spec.apertureDeg},
            {"distance_world", m_distance},
            {"voxelize_ms", m_voxelizeMs},
            {"upload_and_mips_ms", m_uploadMs},
            {"volume_mb", double(std::size_t(s.x) * s.y * s.z * 4) / (1024.0 * 1024.0)},
            {"clamped_segments", m_clampedSegments},
            {"cache", m_lineCache ? m_lineCache->describe() : nlohmann::json("none: cone traced per shaded point")}};
}

}  // namespace tc::gl
