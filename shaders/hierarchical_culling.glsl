// Hierarchical culling of segments and fragments against what earlier depth slices already hide
// (Groß & Gumhold 2020, Sect. 4.3). gl/hierarchical_culling.h rebuilds the pyramid after each
// slice of the sorted draw (shaders/cull_pyramid.comp):
//   CULL_MAX_DEPTH   (opaque): each texel holds the maximum view depth of the pixels it covers;
//                    a segment whose nearest possible depth lies behind every texel it overlaps
//                    cannot pass the depth test anywhere;
//   CULL_MIN_OPACITY (transparent): each texel holds the minimum opacity already blended into the
//                    accumulation target over its pixels (the background is not in it); a segment
//                    all of whose texels exceed uCullThreshold can add at most 1 - threshold.
// Pyramid level L >= 1 (texels of 2^L pixels) is stored row by row at cullPyramid[uCullLevelOffset
// [L - 1]...], uCullLevelSize[L - 1] texels: level 0, the full-resolution copy, is never built.
// Level sizes halve with floor, and the last texel of a row or column also covers the pixels an
// odd size leaves over, so a pixel p lies in texel min(p >> L, size - 1) at every level.
// (A buffer, not a mip-mapped texture: on llvmpipe 22.3, texelFetch of levels >= 1 of an R32F
// texture written with imageStore did not return what glGetTextureImage read back.)
// GLSL 4.50 chunk; needs CULLING plus one of CULL_MAX_DEPTH / CULL_MIN_OPACITY defined.
#include "frame_uniforms.glsl"
#ifndef TC_HIERARCHICAL_CULLING_GLSL
#define TC_HIERARCHICAL_CULLING_GLSL
#ifdef CULLING

#define TC_CULL_MAX_LEVELS 32
layout(std430, binding = SSBO_CULL_PYRAMID) readonly buffer CullPyramid { float cullPyramid[]; };
uniform int uCullLevels;  // stored levels, the last one 1x1
uniform ivec2 uCullLevelSize[TC_CULL_MAX_LEVELS];
uniform int uCullLevelOffset[TC_CULL_MAX_LEVELS];
uniform float uCullThreshold;    // CULL_MIN_OPACITY
// Segments culled in this frame, for timings.csv.
layout(binding = ATOMIC_CULLED_SEGMENTS, offset = 0) uniform atomic_uint uCulledSegments;

// A lower bound of the view depth of any point of the rounded cone (a, b: xyz centre, w radius):
// min(z(x0), z(x1)) - max(r0, r1) with z the depth along the view direction.
float cullNearestDepth(vec4 a, vec4 b) {
    return min(dot(a.xyz - uEye, uForward), dot(b.xyz - uEye, uForward)) - max(a.w, b.w);
}

// Whether what the pyramid texel holds hides a primitive whose nearest view depth is `nearest`.
bool cullTexelHides(float texel, float nearest) {
#ifdef CULL_MAX_DEPTH
    // Relative slack for the float rounding between this bound and the ray-cast depth.
    return nearest > texel * (1.0 + 1e-5) + 1e-30;
#else
    return texel > uCullThreshold;
#endif
}

// Pyramid texel of `pixel` at pyramid level `level` (>= 1).
ivec2 cullTexel(ivec2 pixel, int level) {
    return min(pixel >> level, uCullLevelSize[level - 1] - 1);
}

float cullPyramidTexel(ivec2 texel, int level) {
    return cullPyramid[uCullLevelOffset[level - 1] + texel.y * uCullLevelSize[level - 1].x + texel.x];
}

// Whether every pixel of the window-space box [lo, hi] (pixels, inclusive) is hidden: reads the
// (at most 2 x 2) texels of the level whose texels are at least as large as the box's longest edge.
bool cullBoxHidden(ivec2 lo, ivec2 hi, float nearest) {
    int edge = max(hi.x - lo.x, hi.y - lo.y) + 1;
    int level = clamp(int(ceil(log2(float(edge)))), 1, uCullLevels);
    ivec2 t0 = cullTexel(lo, level), t1 = cullTexel(hi, level);
    for (int y = t0.y; y <= t1.y; ++y)
        for (int x = t0.x; x <= t1.x; ++x)
            if (!cullTexelHides(cullPyramidTexel(ivec2(x, y), level), nearest)) return false;
    return true;
}

// The billboard test: corners in full-image NDC; a billboard entirely off the render target is
// left alone (it rasterizes nothing anyway). The pyramid covers the target (a tile: its pixels).
bool cullBillboard(vec2 ndc[4], float nearest) {
    vec2 lo = targetNdc(min(min(ndc[0], ndc[1]), min(ndc[2], ndc[3])));
    vec2 hi = targetNdc(max(max(ndc[0], ndc[1]), max(ndc[2], ndc[3])));
    vec2 pixelsLo = (0.5 * lo + 0.5) * uTargetSize, pixelsHi = (0.5 * hi + 0.5) * uTargetSize;
    if (any(greaterThan(pixelsLo, uTargetSize)) || any(lessThan(pixelsHi, vec2(0.0)))) return false;
    ivec2 maxPixel = ivec2(uTargetSize) - 1;
    ivec2 p0 = clamp(ivec2(floor(pixelsLo)), ivec2(0), maxPixel);
    ivec2 p1 = clamp(ivec2(floor(pixelsHi)), ivec2(0), maxPixel);
    return cullBoxHidden(p0, p1, nearest);
}

// The per-fragment test, before the ray casting: the level-1 texel holding the fragment.
bool cullFragment(ivec2 pixel, float nearest) {
    return cullTexelHides(cullPyramidTexel(cullTexel(pixel, 1), 1), nearest);
}

#endif  // CULLING
#endif  // TC_HIERARCHICAL_CULLING_GLSL
