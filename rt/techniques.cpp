#include "rt/techniques.h"

namespace tc::rt {

void registerTechniques(TechniqueRegistry& registry) {
    registry.add(raytracedTechnique());
}

}  // namespace tc::rt
