#include "cli/technique_registry.h"

#include "gl/techniques.h"
#include "rt/techniques.h"

namespace tc::cli {

const TechniqueRegistry& techniqueRegistry() {
    // GL techniques first: on a hardware GL, "auto" prefers them in this order.
    static const TechniqueRegistry registry = [] {
        TechniqueRegistry r;
        gl::registerTechniques(r);
        rt::registerTechniques(r);
        return r;
    }();
    return registry;
}

}  // namespace tc::cli
