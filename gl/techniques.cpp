#include "gl/techniques.h"

namespace tc::gl {

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
    const TechniqueDescriptor& d = registry.validate(scene, DataKind::Lines);
    TechniqueData data;
    data.lines = &lines;
    return d.create(scene, data, {});
}

}  // namespace tc::gl
