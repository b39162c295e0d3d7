#include "gl/techniques.h"

namespace tc::gl {

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
    return glRegistry().validate(scene, data.kind).create(scene, data, hooks);
}

}  // namespace tc::gl
