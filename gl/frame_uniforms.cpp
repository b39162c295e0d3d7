#include "gl/frame_uniforms.h"

#include <cmath>

#include "core/shading.h"
#include "gl/bindings.h"
#include "gl/view_window.h"

namespace tc::gl {

FrameUniforms frameUniforms(const FrameSetup& setup, const LightingSpec& lighting) {
    const Camera& cam = setup.camera;
    FrameUniforms u;
    u.eye = cam.eye;
    u.forward = cam.forward();
    u.right = cam.right();
    u.up = cam.trueUp();
    u.orthographic = cam.projection == Projection::Orthographic ? 1 : 0;
    // The pixel footprints of the voxel LoD (shaders/vrc_lod.glsl) and the sphere bounds.
    u.tanHalfFov = std::tan(glm::radians(cam.fovYDeg) * 0.5f);
    u.orthoHalfHeight = 0.5f * cam.orthoHeight;
    setViewWindowUniforms(u, setup);
    // The rays of the full image's pixels: the same three vectors as the CPU ray casters' PixelRays.
    const PixelRays rays(cam, int(u.viewport.x), int(u.viewport.y));
    u.rayBase = glm::vec4(rays.base(), 0.0f);
    u.rayDx = glm::vec4(rays.dx(), 0.0f);
    u.rayDy = glm::vec4(rays.dy(), 0.0f);
    u.lightDir = lightDirectionWorld(lighting, cam);
    u.lightTerms = glm::vec4(lighting.ambient, lighting.diffuse, lighting.specular, lighting.shininess);
    return u;
}

void setRegionUniforms(FrameUniforms& u, const RegionBox& region) {
    u.regionLo = glm::vec4(region.lo, 0.0f);
    u.regionHi = glm::vec4(region.hi, 0.0f);
}

void uploadFrameUniforms(Buffer& buffer, const FrameUniforms& uniforms) {
    if (!buffer) buffer = makeBuffer(sizeof(FrameUniforms), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferSubData(buffer.id(), 0, sizeof(FrameUniforms), &uniforms);
    bindFrameUniforms(buffer);
}

void bindFrameUniforms(const Buffer& buffer) {
    glBindBufferBase(GL_UNIFORM_BUFFER, binding::kFrameUniforms, buffer.id());
}

}  // namespace tc::gl
