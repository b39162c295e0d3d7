#pragma once
// Particles in the CPU ray tracer, with the model of the `spheres` technique: render.technique
// "raytraced" on a particle dataset. One Embree RTC_GEOMETRY_TYPE_SPHERE_POINT geometry
// (primitive i = particle i), built once per data frame. Per pixel-centre ray:
// - Opaque: the first sphere hit; depth / normal / id and the Blinn-Phong colour as
//   core/particle_reference.h's opaque mode (sphereEmission with alpha_rv 0: the surface term alone).
// - Transparent: every sphere the ray crosses, sorted by its entry distance (clamped to 0 when the
//   eye is inside it) and composited front to back ("under"), each with the emission-absorption
//   interior of the sphere glyphs evaluated from the entry / exit pair: opacity from the density
//   model's optical depth over [tNear, tFar] (constant, squared-distance, hollow:
//   core/sphere_glyph.h) and sphereEmission at the entry point. That is
//   core/particle_reference.h's transparent mode (exact for spheres that do not intersect each
//   other), stopping once the accumulated alpha reaches render.raytraced.alpha_cutoff (1 = exact).
//   Hits are gathered by the context filter of rt/hit_collector.h: only entries count (a sphere's
//   exit hit only when the eye is inside it).
// Region (data-parallel rendering, core/region.h): a sphere counts only where its entry point
// (the eye when the eye is inside it) lies in the region box: opaque, the nearest such sphere;
// transparent, every such sphere. Rays are restricted to the box's parameter interval.
// With render.ao: A_O and coloured ambient light L_A at every shaded entry point, weighted as in
// shaders/sphere.frag (rt/particle_ambient.h: "cone_traced" = the GL spheres' volume and cones on
// the CPU, "ray_traced" = hemisphere rays against the same BVH); the ao AOV for opaque spheres.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/region.h"
#include "core/scene.h"
#include "core/stage_sink.h"
#include "core/styled_particles.h"
#include "core/technique.h"
#include "rt/particle_ambient.h"
#include "rt/primary_rays.h"

namespace tc::rt {

class RaytracedParticles final : public Technique {
public:
    // Builds the BVH of `particles` (a copy is kept), and with render.ao the ambient data. Throws
    // InputError for transparency modes the ray tracer does not implement for particles.
    // `region`: data-parallel rendering (see above; AO through region.reduceDensity and
    // region.dataBounds, rt/particle_ambient.h).
    static std::unique_ptr<RaytracedParticles> create(const Scene& scene, const StyledParticles& particles,
                                                      const RegionSetup& region = {});
    ~RaytracedParticles() override;

    // Replaces the particles (a new data frame of a time series): rebuilds the BVH and AO data.
    void upload(const StyledParticles& particles);

    // Renders one frame into `out` as core/particle_reference.h defines it (rgba linear
    // premultiplied; depth / normal / id of the first sphere). Stage "raytrace", items = hits.
    // `window`: the part of the full image this target is (core/tiling.h; tiles, image.samples).
    void render(const Camera& camera, int width, int height, FrameImages& out, StageSink& sink,
                const ImageWindow& window = {}) const;

    void render(const FrameSetup& setup, FrameImages& out, StageSink& sink) override {
        render(setup.camera, setup.width, setup.height, out, sink, setup.window);
    }
    nlohmann::json describe() const override;
    void setTraversal(Traversal t) { m_traversal = t; }
    std::uint64_t lastHitCount() const { return m_lastHits; }

private:
    RaytracedParticles() = default;
    struct Bvh;
    // Bounds of what rays can hit (the BVH's, cut with the region box): tiles missing them are
    // background.
    SceneBounds traceBounds() const;
    // The part of `ray` a region traces: its interval in the box, widened by a rounding margin.
    RayInterval regionRayInterval(const Ray& ray) const;
    // Region opaque rays: the first sphere whose entry point lies in the box, traced from the
    // box's entry past the spheres that belong to other regions. Returns the Embree hits taken.
    std::uint64_t regionFirstHit(const Ray& ray, FirstHit& first) const;

    StyledParticles m_particles;
    RegionSetup m_region;
    SpheresSpec m_spheres;
    LightingSpec m_lighting;
    KeptAovs m_aovs;  // the first-surface AOVs scene.output asks for; the others stay empty
    bool m_transparent = true;
    float m_alphaCutoff = 0.99f;
    std::unique_ptr<Bvh> m_bvh;
    std::optional<AoSpec> m_aoSpec;              // render.ao when enabled
    std::unique_ptr<ParticleAmbient> m_ambient;  // after m_bvh: refers to its scene
    Traversal m_traversal = Traversal::Packet16;
    mutable std::uint64_t m_lastHits = 0;
};

}  // namespace tc::rt
