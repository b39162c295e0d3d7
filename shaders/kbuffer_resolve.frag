// k-buffer resolve: sorts each pixel's remaining entries (kbuffer_insert.frag keeps them
// unsorted), blends them front to back and composites the result under what the insertion pass
// already blended (they all lie behind it), then empties the list for the next frame.
#extension GL_ARB_gpu_shader_int64 : require
#include "kbuffer_common.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    uint base = kbufferBase(ivec2(gl_FragCoord.xy));
    uint64_t e[KBUFFER_K];
    for (int i = 0; i < KBUFFER_K; ++i) {
        e[i] = kbuffer[base + uint(i)];
        kbuffer[base + uint(i)] = kEmpty;
    }
    // Insertion sort by compare-exchange (constant indices once unrolled); kEmpty sorts last.
    for (int i = 1; i < KBUFFER_K; ++i)
        for (int j = i; j > 0; --j) {
            uint64_t lo = min(e[j - 1], e[j]), hi = max(e[j - 1], e[j]);
            e[j - 1] = lo;
            e[j] = hi;
        }
    vec4 sum = vec4(0.0);
    for (int i = 0; i < KBUFFER_K; ++i) {
        if (e[i] == kEmpty) break;
        vec4 c = unpackColor(e[i]);
        sum += (1.0 - sum.a) * vec4(c.rgb * c.a, c.a);
    }
    outColor = sum;
}
