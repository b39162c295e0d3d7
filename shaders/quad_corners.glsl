// The vertex side of gl::QuadIndices (gl/quad_indices.h), the one place the shaders know its index
// pattern: quad q's corners arrive as gl_VertexID 4 q + corner, corners in triangle-strip order
// (bit 0: the rectangle's second x, bit 1: its second y), as the triangles 0-1-2 and 1-3-2. Corner
// 2 is the last, hence provoking, vertex of both, so it alone needs to write the flat outputs.
// GLSL 4.50 chunk for vertex shaders.
#ifndef TC_QUAD_CORNERS_GLSL
#define TC_QUAD_CORNERS_GLSL

uint quadOfVertex() { return uint(gl_VertexID) / 4u; }
int quadCorner() { return gl_VertexID % 4; }
bool isProvokingCorner(int corner) { return corner == 2; }

#endif  // TC_QUAD_CORNERS_GLSL
