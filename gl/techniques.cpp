#include "gl/techniques.h"

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

std::unique_ptr<Technique> createTechnique(const Scene& scene, const StyledLines& lines) {
    static const TechniqueRegistry registry = [] {
        TechniqueRegistry r;
        registerTechniques(r);
        return r;
    }();
    // "auto" as the frame loop resolves it, among the GL techniques: a scene file read as is
    // (render.technique and render.transparency default to "auto") renders as it would on a GPU.
    Scene resolved = scene;
    if (resolved.render.technique.isAuto())
        resolved.render.technique =
            RenderTechnique(registry.resolveAuto(resolved, DataKind::Lines, currentRenderer()).descriptor->name);
    if (resolved.render.transparency == Transparency::Auto)
        if (const TechniqueDescriptor* d = registry.find(resolved.render.technique.name()))
            resolved.render.transparency = resolveTransparency(*d, anyTranslucent(lines)).mode;
    const TechniqueDescriptor& d = registry.validate(resolved, DataKind::Lines);
    TechniqueData data;
    data.lines = &lines;
    return d.create(resolved, data, {});
}

}  // namespace tc::gl
