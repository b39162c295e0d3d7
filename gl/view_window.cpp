#include "gl/view_window.h"

#include <algorithm>
#include <cmath>

#include "gl/gl_util.h"

namespace tc::gl {

void setViewWindowUniforms(GLuint p, const FrameSetup& setup) {
    const ImageWindow& w = setup.window;
    const glm::vec2 offset = glWindowOffset(w, setup.width, setup.height);
    const glm::vec4 ndc = ndcToTarget(w, setup.width, setup.height);
    glProgramUniform2f(p, uniformLocation(p, "uViewport"), float(fullWidthOf(w, setup.width)),
                       float(fullHeightOf(w, setup.height)));
    glProgramUniform2f(p, uniformLocation(p, "uPixelOffset"), offset.x, offset.y);
    glProgramUniform4f(p, uniformLocation(p, "uNdcToTarget"), ndc.x, ndc.y, ndc.z, ndc.w);
    glProgramUniform2f(p, uniformLocation(p, "uTargetSize"), float(setup.width), float(setup.height));
}

void setFrameCameraUniforms(GLuint p, const FrameSetup& setup) {
    const Camera& cam = setup.camera;
    const glm::vec3 eye = cam.eye, fwd = cam.forward(), right = cam.right(), up = cam.trueUp();
    glProgramUniform3fv(p, uniformLocation(p, "uEye"), 1, &eye[0]);
    glProgramUniform3fv(p, uniformLocation(p, "uForward"), 1, &fwd[0]);
    glProgramUniform3fv(p, uniformLocation(p, "uRight"), 1, &right[0]);
    glProgramUniform3fv(p, uniformLocation(p, "uUp"), 1, &up[0]);
    glProgramUniform1i(p, uniformLocation(p, "uOrthographic"), cam.projection == Projection::Orthographic ? 1 : 0);
    glProgramUniform1f(p, uniformLocation(p, "uTanHalfFov"), std::tan(glm::radians(cam.fovYDeg) * 0.5f));
    glProgramUniform1f(p, uniformLocation(p, "uOrthoHalfHeight"), 0.5f * cam.orthoHeight);
    setViewWindowUniforms(p, setup);
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
