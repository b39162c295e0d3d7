#include "gl/ambient_occlusion.h"

#include <chrono>

#include "core/voxel_density.h"
#include "gl/gl_util.h"
#include "gl/line_geometry.h"

namespace tc::gl {

AmbientOcclusion AmbientOcclusion::create(const AoSpec& spec, const StyledLines& lines, const RegionSetup& region) {
    AmbientOcclusion ao;
    ao.m_spec = spec;
    auto t0 = std::chrono::steady_clock::now();
    // Built on the CPU, so a reduction over ranks needs no read-back: it runs before the upload
    // and the mip pyramid is built from the sum.
    DensityGrid grid = buildLineDensity(lines, spec.resolution, region);
    auto t1 = std::chrono::steady_clock::now();
    ao.m_volume = DensityVolume::create(grid);
    glFinish();
    auto t2 = std::chrono::steady_clock::now();
    ao.m_voxelizeMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
    ao.m_uploadMs = std::chrono::duration<double, std::milli>(t2 - t1).count();
    ao.m_clampedSegments = grid.clampedSegments;
    ao.m_distance = spec.distance * glm::length(region.boundsOr(lines.bounds).extent());
    // A tube must not occlude itself: shaders/cone_tracing.glsl ("Self-occlusion") removes the
    // shaded tube's own deposit from every read that can reach it, so the start offset only skips
    // the sub-voxel steps at the apex (one voxel).
    ao.m_startOffset = grid.voxelSize;
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
    if (m_lineCache) m_lineCache->bind();
}

void AmbientOcclusion::buildLineCache(const LineGeometry& geometry, const StyledLines& lines) {
    if (m_spec.cache != AoSpec::Cache::Precomputed) return;
    // One sample per kAoCacheSpacingVoxels of segment length, at least the two ends (shared at
    // polyline joints). The finest read of the tracer is one voxel, but along a tube AO changes
    // slowly (neighbours are mostly parallel); on the 1M-segment tornado (segments ~1-2 voxels)
    // 1 voxel gave 3.0 M samples, 2 voxels with shared joints 1.0 M, and the test scenes'
    // agreement with the exact tracer did not change measurably (tests/gl/ambient_occlusion_test.cpp).
    constexpr float kAoCacheSpacingVoxels = 2.0f;
    m_lineCache = AoLineCache::build(geometry, lines, kAoCacheSpacingVoxels * m_volume.voxelSize(),
                                     [this](GLuint p) { apply(p); });
}

std::vector<std::string> AmbientOcclusion::lineDefines() const {
    std::vector<std::string> defines{"AMBIENT_OCCLUSION", "AO_LINES"};
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
