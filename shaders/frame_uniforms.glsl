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

// The block's values that the line fragment shaders read, handed on as flat varyings: on llvmpipe
// every uniform a fragment shader reads is a conditional scalar load per lane, while a flat varying
// is set once per triangle. Reading the pixel ray's eleven values from the block cost a tenth of
// the opaque visibility pass (docs/performance.md, "Uniforms in fragment shaders"). A flat varying
// is the provoking vertex's value bit for bit, so images do not change. The vertex stages of the
// line and sphere billboards and of the full-screen triangle (FULLSCREEN_FRAME_VARYINGS) #define
// FRAME_VARYINGS_OUT and call writeFrameVaryings() for every vertex that provokes a triangle;
// their fragment shaders #define FRAME_VARYINGS_IN before their first #include, and the names
// below then read the varyings in everything that follows.
#if defined(FRAME_VARYINGS_OUT) || defined(FRAME_VARYINGS_IN)
#ifdef FRAME_VARYINGS_OUT
#define TC_FRAME_VARYING flat out
#else
#define TC_FRAME_VARYING flat in
#endif
// Separate varyings, not an array: the linker drops those a fragment shader does not read. With
// segment_varyings.glsl's seven and the segment id, the transparent shaders use 15 varying slots,
// GL 4.5's minimum GL_MAX_VARYING_VECTORS: a further varying there needs values packed first.
TC_FRAME_VARYING vec4 vFrameEye;      // uEye, uOrthographic
TC_FRAME_VARYING vec4 vFrameForward;  // uForward, uFarDepth
TC_FRAME_VARYING vec4 vFrameRayBase;  // uRayBase.xyz, uPixelOffset.x
TC_FRAME_VARYING vec4 vFrameRayDx;    // uRayDx.xyz, uPixelOffset.y
TC_FRAME_VARYING vec3 vFrameRayDy;
TC_FRAME_VARYING vec3 vFrameLightDir;
TC_FRAME_VARYING vec4 vFrameLightTerms;
#endif
#if defined(FRAME_VARYINGS_OUT)
void writeFrameVaryings() {
    vFrameEye = vec4(uEye, uOrthographic ? 1.0 : 0.0);
    vFrameForward = vec4(uForward, uFarDepth);
    vFrameRayBase = vec4(uRayBase.xyz, uPixelOffset.x);
    vFrameRayDx = vec4(uRayDx.xyz, uPixelOffset.y);
    vFrameRayDy = uRayDy.xyz;
    vFrameLightDir = uLightDir;
    vFrameLightTerms = uLightTerms;
}
#elif defined(FRAME_VARYINGS_IN)
#define uEye (vFrameEye.xyz)
#define uOrthographic (vFrameEye.w != 0.0)
#define uForward (vFrameForward.xyz)
#define uFarDepth (vFrameForward.w)
#define uRayBase (vec4(vFrameRayBase.xyz, 0.0))
#define uRayDx (vec4(vFrameRayDx.xyz, 0.0))
#define uRayDy (vec4(vFrameRayDy, 0.0))
#define uPixelOffset (vec2(vFrameRayBase.w, vFrameRayDx.w))
#define uLightDir (vFrameLightDir)
#define uLightTerms (vFrameLightTerms)
#endif

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
