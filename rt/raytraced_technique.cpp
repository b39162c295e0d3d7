// render.technique "raytraced": the tubes (rt/raytraced_renderer.h) and the spheres
// (rt/raytraced_particles.h) of the GL techniques, ray traced on the CPU with Embree.
#include "core/particle_series.h"
#include "rt/raytraced_particles.h"
#include "rt/raytraced_renderer.h"
#include "rt/techniques.h"

namespace tc::rt {

TechniqueDescriptor raytracedTechnique() {
    TechniqueDescriptor d;
    d.name = "raytraced";
    d.summary =
        "the same tubes and spheres ray traced on the CPU with Embree; transparent modes composite every "
        "hit in exact depth order (up to render.raytraced.alpha_cutoff)";
    d.paper = "tubes: Groß & Gumhold 2020; spheres: Staib, Grottel & Gumhold 2015 (on Embree)";
    d.backend = TechniqueBackend::Cpu;
    d.data = {DataKind::Lines, DataKind::Particles};
    d.autoData = {DataKind::Lines, DataKind::Particles};
    d.transparency = {Transparency::Opaque, Transparency::ObjectOrder, Transparency::KBuffer,
                      Transparency::DepthPeeling};
    d.transparencyAliases = {Transparency::ObjectOrder, Transparency::KBuffer};
    d.exactTransparency = Transparency::DepthPeeling;
    d.ao = {AoSpec::Method::ConeTraced, AoSpec::Method::RayTraced};
    d.regionTransparency = {Transparency::Opaque, Transparency::ObjectOrder, Transparency::KBuffer,
                            Transparency::DepthPeeling};
    // Halos around the tubes, by the exact compositing (rt/raytraced_renderer.h); opaque lines
    // with halos take it too (resolveTransparency).
    d.halo = {Transparency::ObjectOrder, Transparency::KBuffer, Transparency::DepthPeeling};
    d.create = [](const Scene& scene, const TechniqueData& data,
                  const TechniqueHooks& hooks) -> std::unique_ptr<Technique> {
        const RegionSetup region = regionSetup(data, hooks);
        // Hemisphere rays would meet only this rank's share of the data.
        if (region.clips() && scene.render.ao.enabled && scene.render.ao.method == AoSpec::Method::RayTraced)
            refuseRegion(scene, "render.ao.method", "\"ray_traced\"", "\"cone_traced\"");
        if (data.kind == DataKind::Lines) return RaytracedRenderer::create(scene, *data.lines, region);
        return std::make_unique<ParticleSeriesTechnique>(
            scene, *data.particles, data.firstFrame,
            [&scene, region](const StyledParticles& first, ParticleSeriesTechnique::Upload& upload) {
                std::unique_ptr<RaytracedParticles> r = RaytracedParticles::create(scene, first, region);
                upload = [renderer = r.get()](const StyledParticles& p, StageSink& sink) {
                    sink.begin("upload");  // the BVH rebuild
                    renderer->upload(p);
                    sink.setItems(p.size());
                    sink.end();
                };
                return std::unique_ptr<Technique>(std::move(r));
            });
    };
    return d;
}

}  // namespace tc::rt
