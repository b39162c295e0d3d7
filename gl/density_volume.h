#pragma once
// The density volume of line ambient occlusion on the GPU (Groß & Gumhold 2020, Sect. 5.3): a
// single-channel float 3D texture holding core/voxel_density.h's DensityGrid at level 0 and a
// full mip pyramid of box-filtered averages above it, sampled quadrilinearly by
// shaders/cone_tracing.glsl.
//
// Mip pyramid. Level L has GL's size max(1, floor(size >> L)) per axis. A texel of level L+1
// covers the same texture-coordinate box as the level-L texels under it, so it holds the
// *average* of level L over that box, and the mean of every level equals the mean of level 0:
//     mean(level L) * voxelCount(level 0) == grid.total()          (to float rounding)
// For even sizes that box is 2x2x2 texels. For an odd size n -> floor(n / 2) = m the box is
// n / m (2 + 1/m) texels wide and starts at a fractional texel, so shaders/density_mip.comp
// weights each level-L texel by its overlap with the box (a separable area-weighted box filter,
// up to 4 texels per axis). A plain 2x2x2 box drops the odd row; Mesa's glGenerateMipmap keeps
// the mean only on even sizes (+2..3 % of the total on a 37x20x9 grid, measured).
#include <cstddef>
#include <glm/glm.hpp>

#include "core/voxel_density.h"
#include "gl/bindings.h"
#include "gl/objects.h"

namespace tc::gl {

class DensityVolume {
public:
    enum class Format {
        // Default. On llvmpipe cone tracing costs the same with either format (sampling math,
        // not bandwidth, dominates), so R32F's exact totals come for free there.
        R32F,
        // Half the memory (256^3 with mips: 37 MB instead of 73 MB); ~5e-4 relative error per
        // texel, densities below 6e-5 lose precision (AO differed by <= 1.2e-4 in the tests).
        R16F,
    };
    enum class MipMethod {
        // shaders/density_mip.comp: keeps the mean for any size (default). On llvmpipe, 256^3
        // R32F upload + mips took ~280 ms against ~210 ms with glGenerateMipmap (best of 5;
        // the upload alone ~90 ms): a once-per-scene cost worth the exact totals.
        Compute,
        // glGenerateTextureMipmap, for comparison: the same box on power-of-two sizes, but Mesa's
        // filter adds 2-3 % of the total on a 37x20x9 grid.
        GenerateMipmap,
    };
    struct Config {
        Format format = Format::R32F;
        MipMethod mips = MipMethod::Compute;
    };

    // The texture unit the shaders' `uDensity` sampler uses unless the caller picks another.
    static constexpr GLuint kDefaultUnit = binding::kDensityVolume;

    DensityVolume() = default;

    // Uploads `grid` (level 0) and builds the mip pyramid on the GPU. Needs a current context;
    // checks that the grid is non-empty with size.x * size.y * size.z densities and a positive
    // voxel size. The compute program is compiled per call (once per scene). GL state: leaves no
    // program bound and image units 0 and 1 unbound; ends with
    // glMemoryBarrier(texture fetch | texture update), so sampling and glGetTextureImage see the
    // pyramid.
    static DensityVolume create(const DensityGrid& grid, const Config& config);
    static DensityVolume create(const DensityGrid& grid) { return create(grid, Config{}); }

    // The 3D texture: `levels()` levels, min filter GL_LINEAR_MIPMAP_LINEAR (quadrilinear), mag
    // GL_LINEAR, wrap GL_CLAMP_TO_BORDER with a zero border (outside the grid is empty).
    const Texture& texture() const { return m_texture; }
    int levels() const { return m_levels; }
    glm::ivec3 size() const { return m_size; }       // level 0, in voxels
    glm::vec3 origin() const { return m_origin; }    // world position of voxel (0,0,0)'s low corner
    float voxelSize() const { return m_voxelSize; }  // level 0, world units
    const Config& config() const { return m_config; }

    // glBindTextureUnit(unit, texture).
    void bind(GLuint unit = kDefaultUnit) const;
    // Sets the uniforms shaders/cone_tracing.glsl declares, with glProgramUniform* (no program
    // binding): uDensity (= `unit`), uDensityOrigin, uDensityVoxelSize, uDensitySize,
    // uDensityLevels. Uniforms the program does not use are skipped.
    void setUniforms(GLuint program, GLuint unit = kDefaultUnit) const;

    // Size of level `level` per axis, as GL defines it: max(1, size >> level).
    glm::ivec3 levelSize(int level) const;
    // Number of levels of a full pyramid for `size`: floor(log2(max axis)) + 1.
    static int fullLevels(const glm::ivec3& size);

private:
    Config m_config;
    Texture m_texture;
    int m_levels = 0;
    glm::ivec3 m_size{0};
    glm::vec3 m_origin{0.0f};
    float m_voxelSize = 0.0f;
};

}  // namespace tc::gl
