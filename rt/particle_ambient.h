#pragma once
// Ambient occlusion A_O and coloured ambient light L_A of ray-traced particles (the model of
// Staib, Grottel & Gumhold 2015, Eq. 2 and 7), the two render.ao.method variants:
// - "cone_traced": the CPU twin of gl::SphereAmbient (gl/sphere_ambient.h), so the ray-traced
//   spheres look like the GL `spheres` technique's: the spheres voxelized into an RGBA grid exactly
//   as shaders/sphere_voxelize.comp + sphere_volume_resolve.comp do (the overlap weight of
//   Sect. 5.1 in fixed point x opacity255 x colour255, 64-bit sums, the same grid placement), the mip pyramid of
//   shaders/density_mip.comp on four channels, and the cones of shaders/sphere_ambient.glsl
//   (sphereAmbient) ported line by line. With render.ao.cache "precomputed" (the default, as on
//   the GL side) a sphere's six axis-normal points are traced into an ambient cube quantised like
//   packUnorm4x8 and blended by the squared normal (sphere_ambient_cache.comp, sphere.frag); the
//   CPU fills a sphere's cube the first time a ray hits it (values depend only on the sphere, so
//   images do not depend on threads), not for all spheres up front. "none" traces per point.
// - "ray_traced": m x m stratified cosine-weighted hemisphere rays per shaded point against the
//   particle BVH (as rt/ray_traced_ao.h for tubes; deterministic per pixel), each blocked by the
//   first sphere it meets with that sphere's opacity along the ray (the density model's, or the
//   particle opacity when the spheres are drawn opaque), opacity and colour classified by the
//   ambient transfer functions (render.spheres.ambient_*, core/sphere_glyph.h ambientClassify).
//   A_O = (1 - mean blocked)^strength; L_A = the mean of blocked x sphere colour (the light the
//   occluders reflect, as the cones gather it).
// Keep in lock-step with the shaders named above.
#include <embree3/rtcore.h>

#include <atomic>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/mip_pyramid.h"
#include "core/region.h"
#include "core/scene.h"
#include "core/styled_particles.h"

namespace tc::rt {

// The RGBA sphere volume (premultiplied colour, alpha = coverage x opacity) with its mip pyramid.
class SphereVolume {
public:
    // `region` (data-parallel rendering): the grid of region.boundsOr(particles.bounds); with
    // region.reduceDensity only the spheres whose centre lies in region.box deposit and level 0
    // is replaced by the sum over all ranks before the mips (as gl::SphereAmbient::voxelize).
    // `transfer`: the ambient transfer functions (render.spheres.ambient_*) classify each sphere.
    SphereVolume(const AoSpec& spec, const StyledParticles& particles, const RegionSetup& region = {},
                 const AmbientTransfer& transfer = {});

    int levels() const { return m_mip.levels(); }
    const glm::ivec3& size() const { return m_mip.size(); }
    glm::ivec3 levelSize(int level) const { return m_mip.levelSize(level); }
    const glm::vec3& origin() const { return m_origin; }
    float voxelSize() const { return m_voxelSize; }
    // Level `level`, texel (x, y, z), x fastest; (0, 0, 0, 0) outside (the border colour).
    glm::vec4 fetch(int level, int x, int y, int z) const { return m_mip.texel(level, x, y, z); }
    // GL textureLod on a GL_LINEAR_MIPMAP_LINEAR RGBA 3D texture with CLAMP_TO_BORDER (border 0).
    glm::vec4 textureLod(const glm::vec3& uvw, float lod) const { return m_mip.textureLod(uvw, lod); }
    std::size_t bytes() const { return m_mip.bytes(); }

private:
    MipPyramid<glm::vec4> m_mip;
    glm::vec3 m_origin{0.0f};
    float m_voxelSize = 1.0f;
};

struct AmbientTerms {
    float ao = 1.0f;        // A_O: 1 unoccluded .. 0
    glm::vec3 light{0.0f};  // L_A
};

class ParticleAmbient {
public:
    // Builds the volume (cone_traced) for `particles`, which must outlive this object, as must
    // `scene` (ray_traced traces against it; geometry 0 = the particles as sphere points).
    // `opaque`: the spheres are drawn opaque (ray_traced: a hit blocks with the particle opacity).
    // `region`: data bounds and density reduction of data-parallel rendering (SphereVolume).
    ParticleAmbient(const AoSpec& spec, const SpheresSpec& spheres, bool opaque, const StyledParticles& particles,
                    RTCScene scene, const RegionSetup& region = {});
    ~ParticleAmbient();

    // The terms at point p on sphere `sphere` with outward unit normal n, seen from pixel `pixel`
    // (seeds the ray_traced samples). Thread-safe; deterministic.
    AmbientTerms at(std::uint32_t sphere, const glm::vec3& p, const glm::vec3& n, std::uint32_t pixel) const;

    // sphereAmbient of shaders/sphere_ambient.glsl: the traced terms at p with unit normal n.
    AmbientTerms coneTraced(const glm::vec3& p, const glm::vec3& n) const;
    const SphereVolume* volume() const { return m_volume.get(); }
    nlohmann::json describe() const;

private:
    AmbientTerms cached(std::uint32_t sphere, const glm::vec3& n) const;
    AmbientTerms rayTraced(const glm::vec3& p, const glm::vec3& n, std::uint32_t pixel) const;

    AoSpec m_spec;
    SpheresSpec m_spheres;
    bool m_opaque = false;
    const StyledParticles& m_particles;
    RTCScene m_scene = nullptr;
    std::unique_ptr<SphereVolume> m_volume;
    float m_distance = 0;     // world units (cones and rays)
    float m_startOffset = 0;  // cones: world units beyond the surface
    double m_buildMs = 0;
    // Ambient cubes (cache "precomputed"): 6 packUnorm4x8 (L_A, A_O) per sphere, +x -x +y -y +z -z,
    // valid once m_cubeReady[sphere] is set. Atomics: two threads may fill the same sphere at once
    // (with identical values).
    mutable std::unique_ptr<std::atomic<std::uint32_t>[]> m_cube;
    mutable std::unique_ptr<std::atomic<std::uint8_t>[]> m_cubeReady;
};

}  // namespace tc::rt
