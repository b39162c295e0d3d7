#pragma once
// The GLSL side of core/tiling.h's ImageWindow: the view window members of the frame uniform block
// (gl/frame_uniforms.h, shaders/frame_uniforms.glsl) that make a render target an exact off-axis
// window (a tile, a jittered sample) of the full image.
#include "core/technique.h"
#include "gl/gl_api.h"

namespace tc::gl {

struct FrameUniforms;

// Sets uViewport (the full image's size: rays and projected bounds are those of the full image),
// uPixelOffset (full-image window coordinate of the target's origin, jitter included),
// uNdcToTarget (full-image NDC -> target NDC) and uTargetSize of `uniforms`.
void setViewWindowUniforms(FrameUniforms& uniforms, const FrameSetup& setup);

// The current context's limits for one render target (core/tiling.h TileLimits): the smaller of
// GL_MAX_TEXTURE_SIZE and GL_MAX_VIEWPORT_DIMS, and GL_MAX_SHADER_STORAGE_BLOCK_SIZE over
// `storageBytesPerPixel` (0: no per-pixel storage buffer).
TileLimits currentTileLimits(std::size_t storageBytesPerPixel);

}  // namespace tc::gl
