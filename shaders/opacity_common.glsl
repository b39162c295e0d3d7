// Per-pixel fragment lists of opacity optimization (gl/opacity_renderer.cpp): an A-buffer with a
// global atomic node counter and one list head per pixel (Günther, Rössl & Theisel 2013, Sect. 5).
// Each node holds the view depth, the blending parameter w (part index and fraction, kept split
// so the fraction keeps its precision at any part count) and the shaded straight RGBA8 colour,
// each in its own 4-byte array: a shader storage block is capped at
// GL_MAX_SHADER_STORAGE_BLOCK_SIZE (128 MB on llvmpipe), so a 16-byte node struct held at most
// 8.4 M nodes, four 4-byte arrays hold 33.5 M. Nodes past uCapacity are not stored but still
// counted: the renderer reports the overflow.
// GLSL 4.50 chunk; its bindings are kept off the line program's (gl/bindings.h). The lists are read back, sorted and blended on the CPU (gl/opacity_renderer.cpp).

struct PartW {
    float localW;     // t * (parts per line - 1), t the arc-length fraction of the vertex
    uint firstPart;   // global index of the polyline's part 0
};

layout(std430, binding = SSBO_VERTEX_PART_W) readonly buffer VertexPartW { PartW vertexPartW[]; };
layout(std430, binding = SSBO_LIST_HEADS) coherent buffer ListHeads { uint listHead[]; };
layout(std430, binding = SSBO_FRAGMENT_DEPTHS) writeonly buffer FragmentDepths { float fragmentDepth[]; };
layout(std430, binding = SSBO_FRAGMENT_PARTS) writeonly buffer FragmentParts { uint fragmentPart[]; };   // floor(w)
layout(std430, binding = SSBO_FRAGMENT_FRACS) writeonly buffer FragmentFracs { float fragmentFrac[]; };  // w - floor(w); 0 at the last part
layout(std430, binding = SSBO_FRAGMENT_COLORS) writeonly buffer FragmentColors { uint fragmentColor[]; }; // packUnorm4x8, straight
layout(std430, binding = SSBO_FRAGMENT_NEXT) buffer FragmentNext { uint fragmentNext[]; };
layout(std430, binding = SSBO_FRAGMENT_COUNTER) buffer FragmentCounter { uint fragmentCount; };

uniform uint uImageWidth;
uniform uint uCapacity;

const uint kEndOfList = 0xFFFFFFFFu;

uint pixelIndex(ivec2 pixel) { return uint(pixel.y) * uImageWidth + uint(pixel.x); }
