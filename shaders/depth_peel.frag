// Depth peeling, the ground truth of the transparent paths: layer L is the fragment with the
// smallest key (view depth bits, segment id) greater than layer L-1's key, so equal depths (joint
// spheres without cap clipping) are peeled one segment at a time, none lost or doubled.
// PEEL_MIN finds the layer's key per pixel (and counts candidates, so the caller knows when a
// pass produced nothing); PEEL_SHADE blends the fragment with exactly that key "under" the
// accumulated colour. The per-pixel minimum is an ordered read-modify-write (see
// kbuffer_insert.frag for the synchronisation paths) or a 64-bit atomicMin (USE_ATOMIC64).
#extension GL_ARB_gpu_shader_int64 : require
#ifdef USE_ATOMIC64
#extension GL_ARB_shader_atomic_int64 : require
#endif
#if defined(USE_INTERLOCK) && defined(PEEL_MIN)
#extension GL_ARB_fragment_shader_interlock : require
layout(pixel_interlock_ordered) in;
#endif
#include "transparent_fragment.glsl"

layout(std430, binding = SSBO_PEEL_PREVIOUS) readonly buffer PreviousLayer { uint64_t previousKey[]; };
layout(std430, binding = SSBO_PEEL_CURRENT) coherent buffer CurrentLayer { uint64_t currentKey[]; };
layout(std430, binding = SSBO_PEEL_CANDIDATES) buffer Candidates { uint candidates; };

uniform uint uImageWidth;

layout(location = 0) out vec4 outColor;

void main() {
    LineFragment f;
    if (!lineFragment(f)) discard;
    uint pixel = uint(gl_FragCoord.y) * uImageWidth + uint(gl_FragCoord.x);
    uint64_t key = (uint64_t(floatBitsToUint(f.depth)) << 32) | uint64_t(vSegment);
    if (key <= previousKey[pixel]) discard;
#ifdef PEEL_MIN
    atomicAdd(candidates, 1u);
#if defined(USE_ATOMIC64)
    atomicMin(currentKey[pixel], key);
#else
#ifdef USE_INTERLOCK
    beginInvocationInterlockARB();
#endif
    if (key < currentKey[pixel]) currentKey[pixel] = key;
#ifdef USE_INTERLOCK
    endInvocationInterlockARB();
#endif
#endif
    outColor = vec4(0.0);  // blending stays on (llvmpipe ordering); "under" with 0 changes nothing
#else
    if (key != currentKey[pixel]) discard;
    outColor = vec4(f.color.rgb * f.color.a, f.color.a);
#endif
}
