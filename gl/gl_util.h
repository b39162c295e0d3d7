#pragma once
// Small GL functions shared by the passes: uniform look-up, texture read-back, 1D compute
// dispatches over any number of items, the blend state of front-to-back compositing.
#include <cstddef>

#include "core/frame_images.h"
#include "gl/gl_api.h"

namespace tc::gl {

// glGetUniformLocation; -1 for a uniform the program lacks or optimised away, which every
// glProgramUniform* call ignores.
GLint uniformLocation(GLuint program, const char* name);

// Reads level 0 of a 2D texture into `dst` (width x height pixels of `components` values of
// `bytesPerComponent` bytes), flipping rows: GL's row 0 is the bottom, FrameImages' the top.
void readTextureFlipped(GLuint texture, GLenum format, GLenum type, int width, int height, int components,
                        std::size_t bytesPerComponent, void* dst);

// The normal and depth AOVs from an RGBA32F texture (xyz = normal, w = view depth) and the id AOV
// from an R32UI texture, width x height, into `out` (resized, rows flipped as above).
void readNormalDepthId(GLuint normalDepth, GLuint id, int width, int height, FrameImages& out);

// Runs the program in use over the items [first, first + count) in work groups of `groupSize`
// items, in as many dispatches as GL's guaranteed 65,535 groups per dimension need; before each,
// the program's uint uniform `firstUniform` is set to the dispatch's first item.
void dispatchItems(GLuint program, const char* firstUniform, std::size_t first, std::size_t count,
                   std::size_t groupSize);

// Binds `framebuffer` over a width x height viewport, clears colour attachment 0 to transparent
// black, turns off depth test, depth writes and face culling, and blends front to back with the
// "under" operator on premultiplied colour: dst += (1 - dst.a) * src. Blending also keeps
// llvmpipe's per-pixel primitive order, which the read-modify-write passes rely on.
void beginUnderCompositing(GLuint framebuffer, int width, int height);

}  // namespace tc::gl
