// The per-pixel k-buffer (Groß & Gumhold 2020, Sect. 4.2): KBUFFER_K entries per pixel, each a
// 64-bit key: the float bits of the view depth in the high 32 bits (positive floats order like
// unsigned integers) and the straight RGBA8 colour in the low 32 bits. kEmpty (all bits set)
// sorts after every fragment; every slot outside a pixel's ring holds it.
// The entries of a pixel form a ring sorted ascending from slot `head`; the per-pixel header
// holds head | count << 8 (kbuffer_insert.frag has why). GLSL 4.50 chunk; needs KBUFFER_K and, at
// the top of the including shader, #extension GL_ARB_gpu_shader_int64.

// `coherent` only with interlock, whose critical section it serves. Without interlock the lists rely
// on llvmpipe shading a pixel's fragments one at a time on one thread, where it orders nothing; the
// resolve pass follows a memory barrier.
#ifdef USE_INTERLOCK
#define TC_KBUFFER_COHERENT coherent
#else
#define TC_KBUFFER_COHERENT
#endif
layout(std430, binding = SSBO_KBUFFER) TC_KBUFFER_COHERENT buffer KBuffer { uint64_t kbuffer[]; };
layout(std430, binding = SSBO_KBUFFER_HEADERS) TC_KBUFFER_COHERENT buffer KBufferHeaders { uint kbufferHeader[]; };

uniform uint uImageWidth;

const uint64_t kEmpty = 0xFFFFFFFFFFFFFFFFul;

uint kbufferPixel(ivec2 pixel) { return uint(pixel.y) * uImageWidth + uint(pixel.x); }
uint kbufferBase(ivec2 pixel) { return kbufferPixel(pixel) * uint(KBUFFER_K); }

uint64_t packFragment(float depth, vec4 straightColor) {
    return (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(packUnorm4x8(straightColor));
}

vec4 unpackColor(uint64_t entry) { return unpackUnorm4x8(uint(entry & 0xFFFFFFFFul)); }
