// k-buffer resolve: blends each pixel's remaining entries front to back (kbuffer_insert.frag keeps
// them as a ring sorted from slot `head`) and composites the result under what the insertion pass
// already blended (they all lie behind it), then empties the list and its header for the next
// frame. Only the `count` filled slots are read and reset: the others hold kEmpty already, and the
// loop stops when no lane of a block has entries left (most pixels of a frame have none).
#extension GL_ARB_gpu_shader_int64 : require
#include "kbuffer_common.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    uint base = kbufferBase(pixel);
    uint header = kbufferHeader[kbufferPixel(pixel)];
    uint head = header & 0xFFu, count = header >> 8;
    vec4 sum = vec4(0.0);
    for (uint i = 0u; i < count; ++i) {
        uint slot = head + i;
        slot = slot >= uint(KBUFFER_K) ? slot - uint(KBUFFER_K) : slot;
        vec4 c = unpackColor(kbuffer[base + slot]);
        kbuffer[base + slot] = kEmpty;
        sum += (1.0 - sum.a) * vec4(c.rgb * c.a, c.a);
    }
    if (count > 0u) kbufferHeader[kbufferPixel(pixel)] = 0u;
    outColor = sum;
}
