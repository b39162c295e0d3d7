#pragma once
// Quads drawn as indexed triangle pairs: quad q is the triangles (4q, 4q+1, 4q+2) and
// (4q+1, 4q+3, 4q+2), so a vertex shader sees gl_VertexID = 4 q + corner with the corners in
// triangle-strip order. llvmpipe's vertex stage, which runs on one thread, then shades each corner
// once (its vertex cache works on indexed draws only) instead of the six vertices of two
// glDrawArrays triangles, and corner 2, the last and so provoking vertex of both triangles, is the
// only one that writes the flat varyings: 10 % and another 5 % less CPU in the opaque line pass,
// more where depth slices wait for the vertex stage (docs/performance.md, "Indexed quads"). The
// two triangles wind oppositely: face culling stays off. The index pattern is one chunk of quads
// reused through the base vertex, not an index per quad of the data set. shaders/quad_corners.glsl
// is its vertex shader side (which vertex is which corner, which corner provokes); the GL test
// tests/gl/quad_indices_test.cpp checks the two agree.
#include <cstddef>

#include "gl/objects.h"

namespace tc::gl {

class QuadIndices {
public:
    static QuadIndices create();

    // Makes this pattern the element buffer of `vao` (once, after creating both).
    void attachTo(const VertexArray& vao) const;
    // Draws quads [first, first + count) with the bound program and a VAO attachTo'd: their
    // corners get gl_VertexID 4 first ... 4 (first + count) - 1.
    void draw(std::size_t first, std::size_t count) const;

private:
    Buffer m_indices;
};

}  // namespace tc::gl
