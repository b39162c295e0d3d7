// k-buffer insertion: each fragment goes into its pixel's sorted list; when the list is full, the
// nearest of the k + 1 candidates leaves it and is blended into the colour target with the
// "under" operator (the segments are drawn front to back, so it is almost always the nearest
// fragment still to come). No fragment is dropped; kbuffer_resolve.frag blends the rest.
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
    uint64_t evicted = kEmpty;
#ifdef USE_INTERLOCK
    beginInvocationInterlockARB();
#endif
    if (kbuffer[base + uint(KBUFFER_K - 1)] == kEmpty) {
        // Not full: insertion step, carrying the larger entry towards the end.
        uint64_t carry = key;
        for (int i = 0; i < KBUFFER_K; ++i) {
            uint64_t e = kbuffer[base + uint(i)];
            if (carry < e) {
                kbuffer[base + uint(i)] = carry;
                carry = e;
            }
            if (carry == kEmpty) break;
        }
    } else if (key <= kbuffer[base]) {
        evicted = key;  // nearer than everything stored: it leaves at once
    } else {
        evicted = kbuffer[base];
        // Shift entries below the new key one slot towards the front, then place the key.
        int i = 1;
        for (; i < KBUFFER_K; ++i) {
            uint64_t e = kbuffer[base + uint(i)];
            if (e >= key) break;
            kbuffer[base + uint(i - 1)] = e;
        }
        kbuffer[base + uint(i - 1)] = key;
    }
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
