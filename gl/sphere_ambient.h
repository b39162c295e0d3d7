#pragma once
// Ambient occlusion and coloured ambient light of sphere glyphs (Staib, Grottel & Gumhold 2015,
// Sect. 3 and 5.1): the spheres voxelized on the GPU into an RGBA 3D texture (coverage-weighted
// colour, coverage) with a mip pyramid, cone traced per shaded point (shaders/sphere_ambient.glsl)
// into A_O (Eq. 2) and L_A (Eq. 7). Programs that trace cones are compiled with AMBIENT_OCCLUSION.
// With the cache, both terms are traced once per data frame at six points per sphere (normals
// along the axes) and blended per fragment (shaders/sphere_ambient_cache.comp); programs that
// read the cache are compiled with AMBIENT_CACHE too.
#include <cstdint>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/line_set.h"
#include "core/region.h"
#include "core/scene.h"
#include "core/styled_particles.h"
#include "gl/objects.h"

namespace tc::gl {

class SphereAmbient {
public:
    // Compiles the voxelization and mip programs (and the cache build when `cached`). Needs a
    // current context. `transfer`: the ambient transfer functions (render.spheres.ambient_*) that
    // classify each sphere as it is voxelized.
    static SphereAmbient create(const AoSpec& spec, bool cached, const AmbientTransfer& transfer = {});
    bool cached() const { return m_cached; }

    // Voxelizes the spheres into a grid of spec.resolution voxels along the longest axis of
    // `bounds` (cubic voxels) and rebuilds the mip pyramid. Per voxel, the coverage w of a sphere
    // follows Staib et al. 2015, Sect. 5.1: the sphere's volume fraction of the voxel when the
    // voxel contains the whole sphere, 1 when the voxel lies inside the sphere, 0 when they are
    // disjoint, else the fraction of 3x3x3 sub-sample points inside; w x opacity and
    // w x opacity x colour add up over the spheres. Called once per data frame.
    // `region` (data-parallel rendering, core/region.h): with region.reduceDensity, only the
    // spheres whose centre lies in region.box deposit (RegionSetup::densityOwner), and level 0 is
    // read back, replaced by the sum over all ranks and uploaded again before the mips are built;
    // `bounds` must then be the same on every rank (region.dataBounds).
    void voxelize(const StyledParticles& particles, const Bounds& bounds, const RegionSetup& region = {});
    // The same from particle buffers already on the GPU (vec4 centre+radius, vec4 linear RGBA).
    void voxelize(const Buffer& centerRadius, const Buffer& colors, std::size_t count, const Bounds& bounds,
                  const RegionSetup& region = {});

    // Binds the volume (and the cache) and sets the cone tracing uniforms of `program`.
    void apply(GLuint program) const;
    nlohmann::json describe() const;

    // The ambient cube of each sphere (6 packUnorm4x8 of (L_A, A_O): +x, -x, +y, -y, +z, -z),
    // read back, for tests. Empty without the cache.
    std::vector<std::uint32_t> readCache() const;
    // Level 0 of the volume read back (RGBA per voxel, x fastest), for tests.
    std::vector<glm::vec4> readLevel0() const;
    glm::ivec3 size() const { return m_size; }
    float voxelSize() const { return m_voxelSize; }
    glm::vec3 origin() const { return m_origin; }

private:
    SphereAmbient() = default;

    void buildCache(const Buffer& centerRadius, std::size_t count);
    void setTransferUniforms(GLuint program) const;

    AoSpec m_spec;
    AmbientTransfer m_transfer;
    bool m_cached = false;
    Program m_voxelize, m_voxelizeOwned, m_resolve, m_mip, m_cacheBuild;
    Buffer m_cache;  // 6 uint per sphere
    std::size_t m_cacheCount = 0;
    Buffer m_accumulator;  // 8 uint per voxel: 64-bit fixed-point sums of coverage x colour (rgb), coverage
    Texture m_volume;
    int m_levels = 0;
    glm::ivec3 m_size{0};
    glm::vec3 m_origin{0.0f};
    float m_voxelSize = 0;
    float m_distance = 0;
};

}  // namespace tc::gl
