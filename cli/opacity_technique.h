#pragma once
// render.transparency "opacity_optimization" for the frame loop: the GL technique
// (gl/opacity_renderer.h) given the dataset's attribute for render.opacity.importance and, with
// render.opacity.dump_dir (or `tubecast render --dump-system DIR`), a sink writing each frame's
// system (io/opacity_system_dump.h). Always the rasterized path: the importance, the fragment
// lists and the solve need the GL renderer, whatever render.technique "auto" resolved to.
#include <memory>

#include "core/line_set.h"
#include "core/scene.h"
#include "core/styled_lines.h"
#include "gl/technique.h"

namespace tc::cli {

// Throws InputError naming the scene file and key when the importance attribute is missing.
std::unique_ptr<gl::Technique> makeOpacityTechnique(const Scene& scene, const StyledLines& styled, const LineSet& data);

}  // namespace tc::cli
