#pragma once
// The frame loop's one entry point to every technique: the GL ones (gl::createTechnique) and the
// CPU ray tracer of rt/ behind an adapter to gl::Technique, and the choice render.technique
// "auto" makes.
#include <memory>
#include <string>

#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/styled_particles.h"
#include "gl/technique.h"

namespace tc::rt {
class RaytracedParticles;
}

namespace tc::cli {

// Raytraced when `glRenderer` (GL_RENDERER) names a software rasterizer (llvmpipe, softpipe,
// swrast), else Rasterized; non-auto techniques are returned unchanged. `why` gets a log line.
RenderTechnique resolveTechnique(RenderTechnique requested, const std::string& glRenderer, std::string& why);

// The technique for `scene` (render.technique resolved, not Auto). Throws InputError for
// combinations that do not exist (render.ao.method "ray_traced" with "rasterized").
std::unique_ptr<gl::Technique> makeTechnique(const Scene& scene, const StyledLines& lines);

// A particle dataset ray traced (render.technique "raytraced", rt/raytraced_particles.h). `renderer`
// receives the ray tracer inside the technique (valid while it lives) for new data frames.
std::unique_ptr<gl::Technique> makeRaytracedParticles(const Scene& scene, const StyledParticles& particles,
                                                      rt::RaytracedParticles*& renderer);

}  // namespace tc::cli
