#pragma once
// Quads drawn as indexed triangle pairs: quad q is the triangles (4q, 4q+1, 4q+2) and
// (4q+1, 4q+3, 4q+2), so a vertex shader sees gl_VertexID = 4 q + corner with the corners in
// triangle-strip order, and both triangles' provoking (last) vertex is corner 2: only that corner
// needs to write the flat varyings (5 % less CPU in the opaque line pass than corners 2 and 3,
// docs/performance.md). Culling of back faces must be off (the two wind oppositely). Where six
// vertices per quad drawn with glDrawArrays are each shaded, llvmpipe's vertex stage (on one
// thread) shades each corner once, as its vertex cache works on indexed draws only: 10 % less CPU
// in the opaque line pass, more where depth slices wait for it (docs/performance.md, "Indexed
// quads"). The index pattern is one chunk of quads reused through the base vertex, not an index per
// quad of the data set.
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
