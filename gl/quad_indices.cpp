#include "gl/quad_indices.h"

#include <algorithm>
#include <vector>

namespace tc::gl {

namespace {

// Quads per draw of the pattern: 1.5 MB of indices; a million quads take 16 draws of one
// glMultiDrawElementsBaseVertex call.
constexpr std::size_t kChunkQuads = 65536;

}  // namespace

QuadIndices QuadIndices::create() {
    std::vector<GLuint> indices(6 * kChunkQuads);
    const GLuint corners[6] = {0, 1, 2, 1, 3, 2};  // corner 2 last in both: the provoking vertex
    for (std::size_t q = 0; q < kChunkQuads; ++q)
        for (std::size_t c = 0; c < 6; ++c) indices[6 * q + c] = GLuint(4 * q + corners[c]);
    QuadIndices qi;
    qi.m_indices = makeBuffer(indices.size() * sizeof(GLuint), indices.data(), 0);
    return qi;
}

void QuadIndices::attachTo(const VertexArray& vao) const {
    glVertexArrayElementBuffer(vao.id(), m_indices.id());
}

void QuadIndices::draw(std::size_t first, std::size_t count) const {
    std::vector<GLsizei> counts;
    std::vector<const void*> offsets;
    std::vector<GLint> baseVertices;
    for (std::size_t q = first; q < first + count; q += kChunkQuads) {
        counts.push_back(GLsizei(6 * std::min(kChunkQuads, first + count - q)));
        offsets.push_back(nullptr);
        baseVertices.push_back(GLint(4 * q));
    }
    if (counts.empty()) return;
    glMultiDrawElementsBaseVertex(GL_TRIANGLES, counts.data(), GL_UNSIGNED_INT, offsets.data(), GLsizei(counts.size()),
                                  baseVertices.data());
}

}  // namespace tc::gl
