// k-buffer insertion: each fragment goes into its pixel's list of KBUFFER_K entries; when the
// list is full, the nearest of the k + 1 candidates leaves it and is blended into the colour target
// with the "under" operator (the segments are drawn front to back, so it is almost always the
// nearest fragment still to come). No fragment is dropped; kbuffer_resolve.frag sorts and blends
// the rest.
//
// The list is kept unsorted (filled slots first, kEmpty after them): one pass of k loads finds
// the first empty slot and the nearest entry, then at most one store. A sorted list gives the
// same evictions and the same final set, but its shifting costs up to k stores per fragment, and
// on llvmpipe every branch of a shader runs (masked) for every fragment, so the three cases of a
// sorted insertion cost as much as all of them together (docs/performance.md, M2).
//
// The read-modify-write of the list must not race between fragments of one pixel:
// - USE_INTERLOCK: ARB/NV_fragment_shader_interlock orders the critical section;
// - otherwise we rely on llvmpipe shading one pixel's fragments one at a time in primitive order
//   while blending is enabled (../shared/notes/llvmpipe.md); gl/transparent_renderer.cpp enables
//   this path only there and warns on other GPUs without interlock.
#extension GL_ARB_gpu_shader_int64 : require
#ifdef USE_INTERLOCK
#extension GL_ARB_fragment_shader_interlock : require
layout(pixel_interlock_ordered) in;
#endif
#include "transparent_fragment.glsl"
#include "kbuffer_common.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    LineFragment f;
    if (!lineFragment(f)) discard;
    uint64_t key = packFragment(f.depth, f.color);
    uint base = kbufferBase(ivec2(gl_FragCoord.xy));
#ifdef USE_INTERLOCK
    beginInvocationInterlockARB();
#endif
    // Branch-free scan: constant trip count, selects only (unrolled).
    uint64_t nearest = kEmpty;
    int nearestSlot = 0, emptySlot = KBUFFER_K;
    for (int i = KBUFFER_K - 1; i >= 0; --i) {
        uint64_t e = kbuffer[base + uint(i)];
        emptySlot = e == kEmpty ? i : emptySlot;
        bool nearer = e <= nearest;
        nearest = nearer ? e : nearest;
        nearestSlot = nearer ? i : nearestSlot;
    }
    bool full = emptySlot == KBUFFER_K;
    // Full: the nearer of the key and the nearest entry leaves (equal keys are equal entries).
    uint64_t evicted = full ? min(key, nearest) : kEmpty;
    if (!full || key > nearest) kbuffer[base + uint(full ? nearestSlot : emptySlot)] = key;
#ifdef USE_INTERLOCK
    endInvocationInterlockARB();
#endif
    if (evicted == kEmpty) {
        outColor = vec4(0.0);  // blending "under" with 0 leaves the target unchanged
        return;
    }
    vec4 c = unpackColor(evicted);
    outColor = vec4(c.rgb * c.a, c.a);
}
