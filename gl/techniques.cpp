#include "gl/techniques.h"

#include "core/particle_series.h"
#include "core/styling.h"
#include "gl/gl_api.h"

namespace tc::gl {
namespace {

std::string currentRenderer() {
    const GLubyte* r = glGetString(GL_RENDERER);
    return r ? reinterpret_cast<const char*>(r) : "";
}

}  // namespace

void registerTechniques(TechniqueRegistry& registry) {
    registry.add(rasterizedTechnique());
    registry.add(spheresTechnique());
    registry.add(voxelRaycastTechnique());
}

namespace {

const TechniqueRegistry& glRegistry() {
    static const TechniqueRegistry registry = [] {
        TechniqueRegistry r;
        registerTechniques(r);
        return r;
    }();
    return registry;
}

}  // namespace

std::unique_ptr<Technique> createTechnique(const Scene& scene, const StyledLines& lines) {
    TechniqueData data;
    data.lines = &lines;
    return createTechnique(scene, data);
}

std::unique_ptr<Technique> createTechnique(const Scene& scene, const TechniqueData& data, const TechniqueHooks& hooks) {
    const TechniqueRegistry& registry = glRegistry();
    // "auto" as the frame loop resolves it, among the GL techniques: a scene file read as is
    // (render.technique and render.transparency default to "auto") renders as it would on a GPU.
    Scene resolved = scene;
    if (resolved.render.technique.isAuto())
        resolved.render.technique =
            RenderTechnique(registry.resolveAuto(resolved, data.kind, currentRenderer()).descriptor->name);
    if (resolved.render.transparency == Transparency::Auto) {
        const bool translucent = data.kind == DataKind::Lines
                                     ? data.lines && anyTranslucent(*data.lines)
                                     : data.particles && anyTranslucent(resolved.style, *data.particles);
        if (const TechniqueDescriptor* d = registry.find(resolved.render.technique.name()))
            resolved.render.transparency = resolveTransparency(*d, translucent, resolved.style.halo.enabled).mode;
    }
    return registry.validate(resolved, data.kind).create(resolved, data, hooks);
}

}  // namespace tc::gl
