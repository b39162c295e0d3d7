// render.technique "rasterized": the line techniques of the GL rasterizer, one renderer per
// render.transparency mode: opaque rounded cones with deferred shading (gl/rounded_cone_renderer.h),
// object order, k-buffer and depth peeling (gl/transparent_renderer.h), opacity optimization
// (gl/opacity_renderer.h).
#include "core/error.h"
#include "core/line_set.h"
#include "gl/opacity_renderer.h"
#include "gl/rounded_cone_renderer.h"
#include "gl/techniques.h"
#include "gl/transparent_renderer.h"

namespace tc::gl {
namespace {

std::unique_ptr<Technique> createOpacityOptimization(const Scene& scene, const TechniqueData& data,
                                                     const TechniqueHooks& hooks) {
    const OpacityOptimizationSpec& spec = scene.render.opacity;
    const std::vector<float>* attribute = nullptr;
    if (spec.importance == OpacityOptimizationSpec::Importance::Attribute && data.source) {
        const Attribute* a = data.source->attribute(spec.attribute);
        if (!a) {
            std::string names;
            for (const Attribute& x : data.source->attributes) names += (names.empty() ? "" : ", ") + x.name;
            throw InputError(scene.file + ": render.opacity.importance.attribute: the dataset has no attribute \"" +
                             spec.attribute + "\" (it has: " + (names.empty() ? "none" : names) + ")");
        }
        attribute = &a->values;
    }
    return OpacityRenderer::create(scene, *data.lines, attribute, hooks.opacitySystem);
}

}  // namespace

TechniqueDescriptor rasterizedTechnique() {
    TechniqueDescriptor d;
    d.name = "rasterized";
    d.summary =
        "ray-cast rounded cones on view-aligned billboards; opaque (deferred shading), object order, "
        "k-buffer, depth peeling or opacity optimization";
    d.paper = "Groß & Gumhold 2020; opacity optimization: Günther, Rössl & Theisel 2013";
    d.backend = TechniqueBackend::Gl;
    d.data = {DataKind::Lines};
    d.autoData = {DataKind::Lines};
    d.transparency = {Transparency::Opaque, Transparency::ObjectOrder, Transparency::KBuffer,
                      Transparency::DepthPeeling, Transparency::OpacityOptimization};
    d.exactTransparency = Transparency::KBuffer;
    // Halos are drawn by the transparent fragment shader (shaders/transparent_fragment.glsl); the
    // opaque path's visibility buffer keeps one segment id per pixel and has no halo fragment.
    d.halo = {Transparency::ObjectOrder, Transparency::KBuffer, Transparency::DepthPeeling,
              Transparency::OpacityOptimization};
    d.ao = {AoSpec::Method::ConeTraced};
    d.regionTransparency = {Transparency::Opaque, Transparency::ObjectOrder, Transparency::KBuffer,
                            Transparency::DepthPeeling};
    d.check = [](const Scene& scene, DataKind) -> std::optional<SpecProblem> {
        if (scene.render.transparency == Transparency::OpacityOptimization && scene.render.ao.enabled)
            return SpecProblem{"render.ao", "not available with render.transparency \"opacity_optimization\""};
        return std::nullopt;
    };
    d.pixelBuffers = [](const Scene& scene, DataKind) {
        switch (scene.render.transparency) {
            case Transparency::Opaque:
                return RoundedConeRenderer::pixelBuffers(scene);
            case Transparency::OpacityOptimization:
                return OpacityRenderer::pixelBuffers(scene);
            default:
                return TransparentRenderer::pixelBuffers(scene);
        }
    };
    // Opacity optimization solves one system over the whole image's fragments and blends it into
    // the next frame's: its pixels are not independent.
    d.composesWindows = [](const Scene& scene) {
        return scene.render.transparency != Transparency::OpacityOptimization;
    };
    d.create = [](const Scene& scene, const TechniqueData& data,
                  const TechniqueHooks& hooks) -> std::unique_ptr<Technique> {
        const RegionSetup region = regionSetup(data, hooks);
        switch (scene.render.transparency) {
            case Transparency::Opaque:
                return RoundedConeRenderer::create(scene, *data.lines, region);
            case Transparency::OpacityOptimization:
                // One optimisation over all of a pixel's fragments, blended into the next frame's
                // opacities: a region's part of it is not the whole frame's.
                if (region.clips()) refuseRegion(scene, "render.transparency", "opacity_optimization");
                return createOpacityOptimization(scene, data, hooks);
            default:
                return TransparentRenderer::create(scene, *data.lines, region);
        }
    };
    return d;
}

}  // namespace tc::gl
