#include "gl/gl_util.h"

#include <cstring>
#include <vector>

namespace tc::gl {

GLint uniformLocation(GLuint program, const char* name) {
    return glGetUniformLocation(program, name);
}

void readTextureFlipped(GLuint texture, GLenum format, GLenum type, int width, int height, int components,
                        std::size_t bytesPerComponent, void* dst) {
    const std::size_t row = std::size_t(width) * components * bytesPerComponent;
    std::vector<unsigned char> tmp(row * std::size_t(height));
    glGetTextureImage(texture, 0, format, type, GLsizei(tmp.size()), tmp.data());
    auto* out = static_cast<unsigned char*>(dst);
    for (int y = 0; y < height; ++y)
        std::memcpy(out + std::size_t(height - 1 - y) * row, tmp.data() + std::size_t(y) * row, row);
}

}  // namespace tc::gl
