#pragma once
// Small GL functions shared by the passes: uniform look-up and texture read-back.
#include <cstddef>

#include "gl/gl_api.h"

namespace tc::gl {

// glGetUniformLocation; -1 for a uniform the program lacks or optimised away, which every
// glProgramUniform* call ignores.
GLint uniformLocation(GLuint program, const char* name);

// Reads level 0 of a 2D texture into `dst` (width x height pixels of `components` values of
// `bytesPerComponent` bytes), flipping rows: GL's row 0 is the bottom, FrameImages' the top.
void readTextureFlipped(GLuint texture, GLenum format, GLenum type, int width, int height, int components,
                        std::size_t bytesPerComponent, void* dst);

}  // namespace tc::gl
