#pragma once
// The GL techniques' entries of the technique registry (core/technique_registry.h). Each
// descriptor is defined beside its technique; registerTechniques lists them, in the order
// render.technique "auto" considers them.
#include <memory>

#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/technique_registry.h"

namespace tc::gl {

TechniqueDescriptor rasterizedTechnique();    // gl/rasterized_technique.cpp
TechniqueDescriptor spheresTechnique();       // gl/sphere_renderer.cpp
TechniqueDescriptor voxelRaycastTechnique();  // gl/vrc_renderer.cpp

void registerTechniques(TechniqueRegistry& registry);

// The GL technique render.technique names, made for a line dataset through its descriptor (for
// tests and benchmarks that hold styled lines; the frame loop goes through the registry). "auto"
// technique and transparency resolve as in the frame loop, among the GL techniques. Needs a
// current context; throws InputError as TechniqueRegistry::validate.
std::unique_ptr<Technique> createTechnique(const Scene& scene, const StyledLines& lines);
// The same for any dataset with the frame loop's inputs (data-parallel rendering: `data.region`,
// `data.bounds`, `hooks.reduceDensity`).
std::unique_ptr<Technique> createTechnique(const Scene& scene, const TechniqueData& data,
                                           const TechniqueHooks& hooks = {});

}  // namespace tc::gl
