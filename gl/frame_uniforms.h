#pragma once
// What every pass of a frame reads of its camera, view window and light: one std140 uniform
// block (shaders/frame_uniforms.glsl), declared here once more as a C++ struct with the same
// layout (tests/gl/frame_uniforms_test.cpp compares every member's offset and the block size with
// what the GL reports). The technique fills it once per frame or tile and uploads it to a buffer
// bound at binding::kFrameUniforms; passes no longer set camera or light uniforms by name.
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>

#include "core/region.h"
#include "core/scene.h"
#include "core/technique.h"
#include "gl/objects.h"

namespace tc::gl {

// Member for member the block of shaders/frame_uniforms.glsl (the uniform names in comments).
// std140: a vec3 takes 16-byte alignment and is followed here by the 4-byte scalar that shares its
// last word; a GLSL bool is 4 bytes (0 or 1).
struct alignas(16) FrameUniforms {
    // Full-image clip space of the rasterized lines (gl/line_geometry.h; identity elsewhere).
    alignas(16) glm::mat4 viewProj{1.0f};  // uViewProj
    // The camera: Camera::forward/right/trueUp, tan(radians(fovYDeg) / 2), orthoHeight / 2 (the
    // rays themselves come from rayBase / rayDx / rayDy below; shaders/camera.glsl RayCamera).
    alignas(16) glm::vec3 eye{0.0f};      // uEye
    float tanHalfFov = 0;                 // uTanHalfFov
    alignas(16) glm::vec3 forward{0.0f};  // uForward
    float orthoHalfHeight = 0;            // uOrthoHalfHeight
    alignas(16) glm::vec3 right{0.0f};    // uRight
    // Linear depth scale of the passes that write gl_FragDepth = view depth / farDepth.
    float farDepth = 1;              // uFarDepth
    alignas(16) glm::vec3 up{0.0f};  // uUp
    std::uint32_t orthographic = 0;  // uOrthographic
    // Blinn-Phong (shaders/shading.glsl): unit world direction toward the light, and ambient,
    // diffuse, specular, shininess.
    alignas(16) glm::vec3 lightDir{0.0f};  // uLightDir
    // Rasterized lines: clip at the joint planes (render.cap_clipping; gl/line_geometry.h).
    std::uint32_t capClipping = 0;           // uCapClipping
    alignas(16) glm::vec4 lightTerms{0.0f};  // uLightTerms
    // The view window (gl/view_window.h): full-image NDC -> target NDC, the full image's size,
    // the target origin's full-image window coordinate and the target's size, in pixels.
    alignas(16) glm::vec4 ndcToTarget{1.0f, 1.0f, 0.0f, 0.0f};  // uNdcToTarget
    glm::vec2 viewport{0.0f};                                   // uViewport
    glm::vec2 pixelOffset{0.0f};                                // uPixelOffset
    glm::vec2 targetSize{0.0f};                                 // uTargetSize
    // Not in the GLSL block: std140 starts the next vec4 at the following 16-byte boundary. A
    // member, so the bytes are defined (tests/gl/frame_uniforms_test.cpp compares them).
    glm::vec2 padding0{0.0f};
    // Data-parallel rendering: the region box [lo, hi) of core/region.h (xyz; faces may be
    // infinite), read only by programs compiled with REGION_CLIP (shaders/region.glsl).
    alignas(16) glm::vec4 regionLo{-std::numeric_limits<float>::infinity()};  // uRegionLo
    alignas(16) glm::vec4 regionHi{std::numeric_limits<float>::infinity()};   // uRegionHi
    // The pixel rays of the full image (core/camera.h PixelRays base, dx, dy; w unused).
    alignas(16) glm::vec4 rayBase{0.0f};  // uRayBase
    alignas(16) glm::vec4 rayDx{0.0f};    // uRayDx
    alignas(16) glm::vec4 rayDy{0.0f};    // uRayDy
};
static_assert(sizeof(FrameUniforms) % 16 == 0, "std140 blocks are padded to 16 bytes");

// The camera, view window and light of `setup` and `lighting`; viewProj, farDepth, capClipping
// and the region keep their defaults for the technique to set (setRegionUniforms).
FrameUniforms frameUniforms(const FrameSetup& setup, const LightingSpec& lighting);

// The region box of data-parallel rendering (core/region.h) into uRegionLo / uRegionHi.
void setRegionUniforms(FrameUniforms& uniforms, const RegionBox& region);

// Uploads `uniforms` into `buffer` (allocated on first use) and binds it at
// binding::kFrameUniforms (GL_UNIFORM_BUFFER); touches no other state.
void uploadFrameUniforms(Buffer& buffer, const FrameUniforms& uniforms);
// Binds `buffer` (uploaded before) at binding::kFrameUniforms again.
void bindFrameUniforms(const Buffer& buffer);

}  // namespace tc::gl
