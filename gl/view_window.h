#pragma once
// The GLSL side of core/tiling.h's ImageWindow: the uniforms of shaders/view_window.glsl that
// make a render target an exact off-axis window (a tile, a jittered sample) of the full image.
#include "gl/gl_api.h"
#include "core/technique.h"

namespace tc::gl {

// Sets uViewport (the full image's size: rays and projected bounds are those of the full image),
// uPixelOffset (full-image window coordinate of the target's origin, jitter included),
// uNdcToTarget (full-image NDC -> target NDC) and uTargetSize on `program`; names the program
// does not use are skipped. Touches no other GL state.
void setViewWindowUniforms(GLuint program, const FrameSetup& setup);

// The camera uniforms of shaders/frame_uniforms.glsl (uEye, uForward, uRight, uUp,
// uOrthographic, uTanHalfFov, uOrthoHalfHeight) plus the window uniforms above: what every
// technique's ray-casting shader needs of the frame's camera.
void setFrameCameraUniforms(GLuint program, const FrameSetup& setup);

// The current context's limits for one render target (core/tiling.h TileLimits): the smaller of
// GL_MAX_TEXTURE_SIZE and GL_MAX_VIEWPORT_DIMS, and GL_MAX_SHADER_STORAGE_BLOCK_SIZE over
// `storageBytesPerPixel` (0: no per-pixel storage buffer).
TileLimits currentTileLimits(std::size_t storageBytesPerPixel);

}  // namespace tc::gl
