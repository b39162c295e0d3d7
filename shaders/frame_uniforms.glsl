// What every pass of a frame reads of its camera, view window and light: one uniform block, set
// once per frame (or tile) from the same tc::Camera the CPU references use. The C++ twin is
// tc::gl::FrameUniforms (gl/frame_uniforms.h; tests/gl/frame_uniforms_test.cpp compares the
// layouts). GLSL 4.50 chunk, #include'd.
#include "camera.glsl"

layout(std140, binding = UBO_FRAME_UNIFORMS) uniform FrameUniforms {
    mat4 uViewProj;  // full-image clip space of the rasterized lines
    // The camera (RayCamera of camera.glsl).
    vec3 uEye;
    float uTanHalfFov;
    vec3 uForward;
    float uOrthoHalfHeight;
    vec3 uRight;
    float uFarDepth;  // linear depth passes: gl_FragDepth = view depth / uFarDepth
    vec3 uUp;
    bool uOrthographic;
    vec3 uLightDir;      // world space, toward the light
    bool uCapClipping;   // rasterized lines: clip at the joint planes (segment_varyings.glsl)
    vec4 uLightTerms;    // ambient, diffuse, specular, shininess
    // The render target as a window of the full image (core/tiling.h ImageWindow; set by
    // gl/view_window.cpp): a tile and/or a jittered sample position. Rays use the full image's
    // uViewport and full-image window coordinates gl_FragCoord.xy + uPixelOffset; geometry
    // projected to full-image NDC reaches the target through targetNdc. A full window has
    // uPixelOffset = 0 and uNdcToTarget = (1, 1, 0, 0), which leave every value bit-for-bit
    // unchanged.
    vec4 uNdcToTarget;  // full-image NDC -> target NDC: ndc * xy + zw
    vec2 uViewport;     // the full image in pixels
    vec2 uPixelOffset;  // full-image window coordinate of the target's origin (y up)
    vec2 uTargetSize;   // the render target in pixels
    // Data-parallel rendering: the region box [lo, hi) of core/region.h in xyz (faces may be
    // infinite); read only by programs compiled with REGION_CLIP (region.glsl).
    vec4 uRegionLo;
    vec4 uRegionHi;
    // The full image's pixel rays as base + x dx + y dy (core/camera.h PixelRays; xyz).
    vec4 uRayBase;
    vec4 uRayDx;
    vec4 uRayDy;
};

vec2 targetNdc(vec2 ndc) { return ndc * uNdcToTarget.xy + uNdcToTarget.zw; }

RayCamera frameCamera() {
    return RayCamera(uEye, uForward, uTanHalfFov, uOrthoHalfHeight, uOrthographic, uViewport, uPixelOffset,
                     uRayBase.xyz, uRayDx.xyz, uRayDy.xyz);
}

// View-space depth of a hit at parameter t: distance along the viewing direction. Orthographic
// rays start on the eye plane and run along it, so t is the depth.
float viewDepth(Ray ray, float t) {
    return uOrthographic ? t : t * dot(ray.dir, uForward);
}

// inRegion (programs compiled with REGION_CLIP): after the block, whose box it reads.
#include "region.glsl"
