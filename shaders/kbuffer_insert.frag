// k-buffer insertion: each fragment goes into its pixel's list of KBUFFER_K entries; when the
// list is full, the nearest of the k + 1 candidates leaves it and is blended into the colour target
// with the "under" operator (the segments are drawn front to back, so it is almost always the
// nearest fragment still to come). No fragment is dropped; kbuffer_resolve.frag blends the rest.
//
// The list is a ring kept sorted ascending from slot `head` (per-pixel header: head | count << 8).
// The segments arrive sorted front to back, so a fragment is almost always behind every entry:
// then it replaces the nearest entry (which leaves) and the ring turns by one slot. That common
// case reads the header, the nearest and the last entry and writes the key and the header; a
// fragment that lands inside the list shifts the entries behind it one slot, in a loop (on
// llvmpipe a loop stops when no lane needs another iteration, while both sides of an `if` always
// run masked). An unsorted list needs all k loads per fragment to find the nearest entry (every
// SSBO access is a per-lane scalar loop on llvmpipe); measured on llvmpipe, this insertion costs
// about the same as that unrolled scan, but the header lets kbuffer_resolve.frag read only the
// filled slots, which made the resolve 4-7x cheaper (docs/performance.md, "Design notes"). The
// evictions, hence the image, are the same for any list layout: the nearer of the fragment and
// the nearest entry leaves.
//
// The read-modify-write of the list must not race between fragments of one pixel:
// - USE_INTERLOCK: ARB/NV_fragment_shader_interlock orders the critical section;
// - otherwise we rely on llvmpipe shading one pixel's fragments one at a time in primitive order
//   while blending is enabled; gl/transparent_renderer.cpp enables
//   this path only there and warns on other GPUs without interlock.
#extension GL_ARB_gpu_shader_int64 : require
#ifdef USE_INTERLOCK
#extension GL_ARB_fragment_shader_interlock : require
layout(pixel_interlock_ordered) in;
#endif
#include "transparent_fragment.glsl"
#include "kbuffer_common.glsl"

layout(location = 0) out vec4 outColor;

// Physical slot of the ring's logical position i (< KBUFFER_K) from `head`.
uint ringSlot(uint head, uint i) {
    uint s = head + i;
    return s >= uint(KBUFFER_K) ? s - uint(KBUFFER_K) : s;
}

void main() {
    LineFragment f;
    if (!lineFragment(f)) discard;
    uint64_t key = packFragment(f.depth, f.color);
    uint pixel = kbufferPixel(ivec2(gl_FragCoord.xy));
    uint base = pixel * uint(KBUFFER_K);
#ifdef USE_INTERLOCK
    beginInvocationInterlockARB();
#endif
    uint header = kbufferHeader[pixel];
    uint head = header & 0xFFu, count = header >> 8;
    bool full = count == uint(KBUFFER_K);
    // Not full: head is 0 and slot 0 may be empty; the value is only used when full.
    uint64_t nearest = kbuffer[base + head];
    // Full: the nearer of the key and the nearest entry leaves (equal keys are equal entries).
    bool keyLeaves = full && key <= nearest;
    uint64_t evicted = full ? (keyLeaves ? key : nearest) : kEmpty;
    if (!keyLeaves) {
        // The nearest entry left: the ring turns, its slot becomes the last logical position.
        uint first = full ? ringSlot(head, 1u) : head;
        uint n = full ? uint(KBUFFER_K) - 1u : count;  // entries staying, logical 0 .. n - 1
        uint j = n;
        while (j > 0u) {
            uint64_t e = kbuffer[base + ringSlot(first, j - 1u)];
            if (e <= key) break;
            kbuffer[base + ringSlot(first, j)] = e;
            --j;
        }
        kbuffer[base + ringSlot(first, j)] = key;
        kbufferHeader[pixel] = first | ((n + 1u) << 8);
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
