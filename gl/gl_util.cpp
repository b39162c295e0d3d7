#include "gl/gl_util.h"

#include <algorithm>
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

void readNormalDepthId(GLuint normalDepth, GLuint id, int width, int height, FrameImages& out) {
    const std::size_t n = std::size_t(width) * std::size_t(height);
    std::vector<float> nd(4 * n);
    readTextureFlipped(normalDepth, GL_RGBA, GL_FLOAT, width, height, 4, sizeof(float), nd.data());
    out.id.resize(n);
    readTextureFlipped(id, GL_RED_INTEGER, GL_UNSIGNED_INT, width, height, 1, sizeof(GLuint), out.id.data());
    out.normal.resize(3 * n);
    out.depth.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) out.normal[3 * i + c] = nd[4 * i + c];
        out.depth[i] = nd[4 * i + 3];
    }
}

void dispatchItems(GLuint program, const char* firstUniform, std::size_t first, std::size_t count,
                   std::size_t groupSize) {
    constexpr std::size_t kMaxGroups = 65535;
    const std::size_t perDispatch = kMaxGroups * groupSize;
    const GLint location = uniformLocation(program, firstUniform);
    for (std::size_t begin = first; begin < first + count; begin += perDispatch) {
        const std::size_t n = std::min(perDispatch, first + count - begin);
        glProgramUniform1ui(program, location, GLuint(begin));
        glDispatchCompute(GLuint((n + groupSize - 1) / groupSize), 1, 1);
    }
}

void beginUnderCompositing(GLuint framebuffer, int width, int height) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width, height);
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, zero);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
}

}  // namespace tc::gl
