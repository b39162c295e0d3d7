#include "gl/sphere_ambient.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/error.h"
#include "core/sphere_glyph.h"
#include "gl/bindings.h"
#include "gl/density_volume.h"
#include "gl/gl_util.h"
#include "gl/shader_library.h"

namespace tc::gl {

namespace {

constexpr GLuint kGroup = 64;  // local_size_x of the voxelize and resolve shaders
constexpr std::size_t kMaxGroups = 65535;
constexpr glm::ivec3 kMipGroup(8, 8, 1);  // shaders/density_mip.comp

GLuint divUp(int n, int d) {
    return GLuint((n + d - 1) / d);
}

}  // namespace

SphereAmbient SphereAmbient::create(const AoSpec& spec, bool cached, const AmbientTransfer& transfer) {
    TC_CHECK_OP(transfer.opacity.size(), <=, std::size_t(AmbientTransfer::kMaxPoints));
    TC_CHECK_OP(transfer.emission.size(), <=, std::size_t(AmbientTransfer::kMaxPoints));
    SphereAmbient a;
    a.m_spec = spec;
    a.m_transfer = transfer;
    a.m_cached = cached;
    if (cached) a.m_cacheBuild = compileProgram({{GL_COMPUTE_SHADER, "sphere_ambient_cache.comp"}});
    a.m_voxelize = compileProgram({{GL_COMPUTE_SHADER, "sphere_voxelize.comp"}});
    a.setTransferUniforms(a.m_voxelize.id());
    a.m_resolve = compileProgram({{GL_COMPUTE_SHADER, "sphere_volume_resolve.comp"}});
    // The line density volume's mip filter (mean-preserving for any size), on four channels.
    a.m_mip = compileProgram({{GL_COMPUTE_SHADER, "density_mip.comp"}}, {"DENSITY_IMAGE_FORMAT rgba32f", "MIP_RGBA"});
    return a;
}

void SphereAmbient::voxelize(const StyledParticles& particles, const Bounds& bounds, const RegionSetup& region) {
    Buffer centerRadius = makeBuffer(particles.size() * sizeof(glm::vec4), particles.centerRadius.data());
    Buffer colors = makeBuffer(particles.size() * sizeof(glm::vec4), particles.color.data());
    voxelize(centerRadius, colors, particles.size(), bounds, region);
}

void SphereAmbient::voxelize(const Buffer& centerRadius, const Buffer& colors, std::size_t count, const Bounds& bounds,
                             const RegionSetup& region) {
    // The grid: spec.resolution cubic voxels along the longest axis of the spheres' bounds.
    glm::vec3 extent = bounds.empty() ? glm::vec3(1.0f) : glm::max(bounds.extent(), glm::vec3(1e-6f));
    const float longest = std::max({extent.x, extent.y, extent.z});
    const float voxel = longest / float(m_spec.resolution);
    glm::ivec3 size = glm::clamp(glm::ivec3(glm::ceil(extent / voxel)), glm::ivec3(1), glm::ivec3(m_spec.resolution));
    const glm::vec3 origin = bounds.empty() ? glm::vec3(0.0f) : bounds.lo;
    const std::size_t voxels = std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z);
    if (size != m_size) {
        m_size = size;
        m_levels = DensityVolume::fullLevels(size);
        m_volume = Texture::create(GL_TEXTURE_3D);
        glTextureStorage3D(m_volume.id(), m_levels, GL_RGBA32F, size.x, size.y, size.z);
        setVolumeSampling(m_volume.id(), true, VolumeEdge::ZeroBorder);
        m_accumulator = makeBuffer(voxels * 8 * sizeof(GLuint));  // shaders/sphere_voxelize.comp
        const GLuint zero = 0;
        glClearNamedBufferData(m_accumulator.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    }
    m_origin = origin;
    m_voxelSize = voxel;
    m_distance = m_spec.distance * glm::length(extent);

    // Only the owned spheres with a reduction (a variant, so the plain voxelization is unchanged).
    const RegionBox owner = region.densityOwner();
    if (!owner.unbounded() && !m_voxelizeOwned) {
        m_voxelizeOwned = compileProgram({{GL_COMPUTE_SHADER, "sphere_voxelize.comp"}}, {"DENSITY_OWNER"});
        setTransferUniforms(m_voxelizeOwned.id());
    }
    GLuint p = owner.unbounded() ? m_voxelize.id() : m_voxelizeOwned.id();
    if (!owner.unbounded()) {
        glProgramUniform3fv(p, uniformLocation(p, "uOwnerLo"), 1, &owner.lo[0]);
        glProgramUniform3fv(p, uniformLocation(p, "uOwnerHi"), 1, &owner.hi[0]);
    }
    glProgramUniform1ui(p, uniformLocation(p, "uCount"), GLuint(count));
    glProgramUniform3fv(p, uniformLocation(p, "uOrigin"), 1, &origin[0]);
    glProgramUniform1f(p, uniformLocation(p, "uVoxelSize"), voxel);
    glProgramUniform3i(p, uniformLocation(p, "uSize"), size.x, size.y, size.z);
    glUseProgram(p);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereCenterRadius, centerRadius.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereColors, colors.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereAccumulator, m_accumulator.id());
    dispatchItems(p, "uFirst", 0, count, kGroup);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    p = m_resolve.id();
    glProgramUniform3i(p, uniformLocation(p, "uSize"), size.x, size.y, size.z);
    glUseProgram(p);
    glBindImageTexture(binding::kSphereVolumeOut, m_volume.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    const std::size_t groups = (voxels + kGroup - 1) / kGroup;
    const std::size_t groupsX = std::min(groups, kMaxGroups);
    glDispatchCompute(GLuint(groupsX), GLuint((groups + groupsX - 1) / groupsX), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    if (region.reduceDensity) {
        // Every rank's spheres: level 0 is linear in the deposits (sphere_volume_resolve.comp), so
        // the sum of the ranks' levels is the level of all spheres (to float rounding); the mips
        // below are built from the sum.
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        std::vector<float> level0(4 * voxels);
        glGetTextureImage(m_volume.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(level0.size() * sizeof(float)), level0.data());
        region.reduceDensity(level0);
        TC_CHECK_OP(level0.size(), ==, 4 * voxels);
        glTextureSubImage3D(m_volume.id(), 0, 0, 0, 0, size.x, size.y, size.z, GL_RGBA, GL_FLOAT, level0.data());
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }

    p = m_mip.id();
    glUseProgram(p);
    for (int level = 0; level + 1 < m_levels; ++level) {
        const glm::ivec3 src = glm::max(size >> level, glm::ivec3(1));
        const glm::ivec3 dst = glm::max(size >> (level + 1), glm::ivec3(1));
        glProgramUniform3i(p, uniformLocation(p, "uSourceSize"), src.x, src.y, src.z);
        glProgramUniform3i(p, uniformLocation(p, "uTargetSize"), dst.x, dst.y, dst.z);
        glBindImageTexture(binding::kMipSource, m_volume.id(), level, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(binding::kMipTarget, m_volume.id(), level + 1, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(divUp(dst.x, kMipGroup.x), divUp(dst.y, kMipGroup.y), divUp(dst.z, kMipGroup.z));
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    glBindImageTexture(binding::kMipSource, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(binding::kMipTarget, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glUseProgram(0);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    if (m_cached) buildCache(centerRadius, count);
}

void SphereAmbient::setTransferUniforms(GLuint p) const {
    const auto set = [p](const std::vector<glm::vec2>& points, const char* count, const char* array) {
        glProgramUniform1i(p, uniformLocation(p, count), GLint(points.size()));
        if (!points.empty()) glProgramUniform2fv(p, uniformLocation(p, array), GLsizei(points.size()), &points[0][0]);
    };
    set(m_transfer.opacity, "uAmbientOpacityCount", "uAmbientOpacity");
    set(m_transfer.emission, "uAmbientEmissionCount", "uAmbientEmission");
}

void SphereAmbient::buildCache(const Buffer& centerRadius, std::size_t count) {
    const std::size_t items = 6 * count;
    if (items == 0) return;
    if (items > m_cacheCount) {
        m_cache = makeBuffer(items * sizeof(GLuint));
        m_cacheCount = items;
    }
    GLuint p = m_cacheBuild.id();
    apply(p);
    glProgramUniform1ui(p, uniformLocation(p, "uCount"), GLuint(items));
    glUseProgram(p);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereCenterRadius, centerRadius.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereAmbientCube, m_cache.id());
    dispatchItems(p, "uFirst", 0, items, kGroup);
    glUseProgram(0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

std::vector<std::uint32_t> SphereAmbient::readCache() const {
    std::vector<std::uint32_t> v(m_cached ? m_cacheCount : 0);
    if (!v.empty()) glGetNamedBufferSubData(m_cache.id(), 0, GLsizeiptr(v.size() * sizeof(GLuint)), v.data());
    return v;
}

void SphereAmbient::apply(GLuint p) const {
    glBindTextureUnit(binding::kSphereVolume, m_volume.id());
    glProgramUniform1i(p, uniformLocation(p, "uSphereVolume"), GLint(binding::kSphereVolume));
    glProgramUniform3fv(p, uniformLocation(p, "uSphereVolumeOrigin"), 1, &m_origin[0]);
    glProgramUniform1f(p, uniformLocation(p, "uSphereVolumeVoxel"), m_voxelSize);
    glProgramUniform3i(p, uniformLocation(p, "uSphereVolumeSize"), m_size.x, m_size.y, m_size.z);
    glProgramUniform1i(p, uniformLocation(p, "uSphereVolumeLevels"), m_levels);
    glProgramUniform1i(p, uniformLocation(p, "uAoCones"), m_spec.cones);
    glProgramUniform1f(p, uniformLocation(p, "uAoAperture"), glm::radians(m_spec.apertureDeg));
    glProgramUniform1f(p, uniformLocation(p, "uAoDistance"), m_distance);
    glProgramUniform1f(p, uniformLocation(p, "uAoStrength"), m_spec.strength);
    // The shaded sphere deposited itself around the point: start one and a half voxels out.
    glProgramUniform1f(p, uniformLocation(p, "uAoStartOffset"), 1.5f * m_voxelSize);
    if (m_cached && m_cache.id()) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereAmbientCube, m_cache.id());
}

nlohmann::json SphereAmbient::describe() const {
    return {{"method", "voxel cone tracing of a GPU sphere voxelization (RGBA: coverage x opacity, colour)"},
            {"size", {m_size.x, m_size.y, m_size.z}},
            {"voxel_size", m_voxelSize},
            {"cones", m_spec.cones},
            {"aperture_deg", m_spec.apertureDeg},
            {"distance", m_distance},
            {"strength", m_spec.strength},
            {"ambient_transfer", describeAmbientTransfer(m_transfer)},
            {"cache", m_cached ? "ambient cube per sphere (6 traced normals, once per data frame)" : "none"}};
}

std::vector<glm::vec4> SphereAmbient::readLevel0() const {
    std::vector<glm::vec4> v(std::size_t(m_size.x) * m_size.y * m_size.z);
    glGetTextureImage(m_volume.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(v.size() * sizeof(glm::vec4)), v.data());
    return v;
}

}  // namespace tc::gl
