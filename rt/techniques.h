#pragma once
// The CPU techniques' entries of the technique registry (core/technique_registry.h); they need no
// GL context. registerTechniques lists them, in the order render.technique "auto" considers them.
#include "core/technique_registry.h"

namespace tc::rt {

TechniqueDescriptor raytracedTechnique();  // rt/raytraced_technique.cpp

void registerTechniques(TechniqueRegistry& registry);

}  // namespace tc::rt
