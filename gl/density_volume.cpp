#include "gl/density_volume.h"

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mip_pyramid.h"
#include "gl/bindings.h"
#include "gl/gl_api.h"
#include "gl/shader_library.h"

namespace tc::gl {
namespace {

// shaders/density_mip.comp's local size.
constexpr glm::ivec3 kMipGroup(8, 8, 1);

int divUp(int a, int b) {
    return (a + b - 1) / b;
}

void setIvec3(GLuint program, const char* name, const glm::ivec3& v) {
    glProgramUniform3i(program, glGetUniformLocation(program, name), v.x, v.y, v.z);
}

}  // namespace

int DensityVolume::fullLevels(const glm::ivec3& size) {
    return fullMipLevels(size);
}

glm::ivec3 DensityVolume::levelSize(int level) const {
    return glm::max(glm::ivec3(1), m_size >> level);
}

DensityVolume DensityVolume::create(const DensityGrid& grid, const Config& config) {
    TC_CHECK(grid.size.x >= 1 && grid.size.y >= 1 && grid.size.z >= 1);
    TC_CHECK_OP(grid.density.size(), ==, grid.voxelCount());
    TC_CHECK(grid.voxelSize > 0.0f);

    DensityVolume volume;
    volume.m_config = config;
    volume.m_size = grid.size;
    volume.m_origin = grid.origin;
    volume.m_voxelSize = grid.voxelSize;
    volume.m_levels = fullLevels(grid.size);

    const bool half = config.format == Format::R16F;
    const GLenum internalFormat = half ? GL_R16F : GL_R32F;

    volume.m_texture = Texture::create(GL_TEXTURE_3D);
    const GLuint tex = volume.m_texture.id();
    glTextureStorage3D(tex, volume.m_levels, internalFormat, grid.size.x, grid.size.y, grid.size.z);
    // Rows of a 1-voxel-wide R32F grid are 4 bytes: the default unpack alignment of 4 holds.
    glTextureSubImage3D(tex, 0, 0, 0, 0, grid.size.x, grid.size.y, grid.size.z, GL_RED, GL_FLOAT, grid.density.data());
    setVolumeSampling(tex, true, VolumeEdge::ZeroBorder);

    if (config.mips == MipMethod::GenerateMipmap) {
        glGenerateTextureMipmap(tex);
    } else if (volume.m_levels > 1) {
        Program program = compileProgram({{GL_COMPUTE_SHADER, "density_mip.comp"}},
                                         {std::string("DENSITY_IMAGE_FORMAT ") + (half ? "r16f" : "r32f")});
        glUseProgram(program.id());
        for (int level = 0; level + 1 < volume.m_levels; ++level) {
            const glm::ivec3 source = volume.levelSize(level);
            const glm::ivec3 target = volume.levelSize(level + 1);
            setIvec3(program.id(), "uSourceSize", source);
            setIvec3(program.id(), "uTargetSize", target);
            glBindImageTexture(binding::kMipSource, tex, level, GL_TRUE, 0, GL_READ_ONLY, internalFormat);
            glBindImageTexture(binding::kMipTarget, tex, level + 1, GL_TRUE, 0, GL_WRITE_ONLY, internalFormat);
            glDispatchCompute(divUp(target.x, kMipGroup.x), divUp(target.y, kMipGroup.y), divUp(target.z, kMipGroup.z));
            // The next level reads what this one wrote.
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
        glBindImageTexture(binding::kMipSource, 0, 0, GL_FALSE, 0, GL_READ_ONLY, internalFormat);
        glBindImageTexture(binding::kMipTarget, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, internalFormat);
        glUseProgram(0);
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    return volume;
}

void DensityVolume::bind(GLuint unit) const {
    glBindTextureUnit(unit, m_texture.id());
}

void DensityVolume::setUniforms(GLuint program, GLuint unit) const {
    // glProgramUniform* ignores location -1 (a uniform the program optimised away).
    glProgramUniform1i(program, glGetUniformLocation(program, "uDensity"), GLint(unit));
    glProgramUniform3f(program, glGetUniformLocation(program, "uDensityOrigin"), m_origin.x, m_origin.y, m_origin.z);
    glProgramUniform1f(program, glGetUniformLocation(program, "uDensityVoxelSize"), m_voxelSize);
    setIvec3(program, "uDensitySize", m_size);
    glProgramUniform1i(program, glGetUniformLocation(program, "uDensityLevels"), m_levels);
}

}  // namespace tc::gl
