#include "gl/view_window.h"

#include <algorithm>

#include "gl/frame_uniforms.h"

namespace tc::gl {

void setViewWindowUniforms(FrameUniforms& u, const FrameSetup& setup) {
    const ImageWindow& w = setup.window;
    u.viewport = glm::vec2(float(fullWidthOf(w, setup.width)), float(fullHeightOf(w, setup.height)));
    u.pixelOffset = glWindowOffset(w, setup.width, setup.height);
    u.ndcToTarget = ndcToTarget(w, setup.width, setup.height);
    u.targetSize = glm::vec2(float(setup.width), float(setup.height));
}

TileLimits currentTileLimits(std::size_t storageBytesPerPixel) {
    GLint maxTexture = 0, maxViewport[2] = {0, 0};
    GLint64 maxBlock = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    TileLimits limits;
    limits.maxEdge = std::max(0, std::min({maxTexture, maxViewport[0], maxViewport[1]}));
    if (storageBytesPerPixel > 0 && maxBlock > 0) limits.maxPixels = std::size_t(maxBlock) / storageBytesPerPixel;
    return limits;
}

}  // namespace tc::gl
