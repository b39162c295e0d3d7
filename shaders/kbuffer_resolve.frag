// k-buffer resolve: blends each pixel's remaining entries front to back and composites the result
// under what the insertion pass already blended (they all lie behind it), then empties the list
// for the next frame.
#extension GL_ARB_gpu_shader_int64 : require
#include "kbuffer_common.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    uint base = kbufferBase(ivec2(gl_FragCoord.xy));
    vec4 sum = vec4(0.0);
    for (int i = 0; i < KBUFFER_K; ++i) {
        uint64_t e = kbuffer[base + uint(i)];
        if (e == kEmpty) break;
        vec4 c = unpackColor(e);
        sum += (1.0 - sum.a) * vec4(c.rgb * c.a, c.a);
        kbuffer[base + uint(i)] = kEmpty;
    }
    outColor = sum;
}
