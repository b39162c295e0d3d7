// Per-pixel fragment lists of opacity optimization (gl/opacity_renderer.cpp): an A-buffer with a
// global atomic node counter and one list head per pixel (Günther, Rössl & Theisel 2013, Sect. 5).
// Each node holds the view depth, the blending parameter w (part index and fraction, kept split
// so the fraction keeps its precision at any part count) and the shaded straight RGBA8 colour.
// Nodes past uCapacity are not stored but still counted: the renderer reports the overflow.
// GLSL 4.50 chunk; bindings 11-15 (0-6 line data, 7-10 transparent renderer). The lists are read
// back, sorted and blended on the CPU (gl/opacity_renderer.cpp).

struct PartW {
    float localW;     // t * (parts per line - 1), t the arc-length fraction of the vertex
    uint firstPart;   // global index of the polyline's part 0
};

struct FragmentNode {
    float depth;
    uint part;   // floor(w)
    float frac;  // w - floor(w); 0 at a polyline's last part
    uint color;  // packUnorm4x8 of the straight shaded colour
};

layout(std430, binding = 11) readonly buffer VertexPartW { PartW vertexPartW[]; };
layout(std430, binding = 12) coherent buffer ListHeads { uint listHead[]; };
layout(std430, binding = 13) buffer FragmentNodes { FragmentNode fragmentNode[]; };
layout(std430, binding = 14) buffer FragmentNext { uint fragmentNext[]; };
layout(std430, binding = 15) buffer FragmentCounter { uint fragmentCount; };

uniform uint uImageWidth;
uniform uint uCapacity;

const uint kEndOfList = 0xFFFFFFFFu;

uint pixelIndex(ivec2 pixel) { return uint(pixel.y) * uImageWidth + uint(pixel.x); }
