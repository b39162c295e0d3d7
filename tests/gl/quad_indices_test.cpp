// gl::QuadIndices against its shader side (shaders/quad_corners.glsl): which vertex is which
// corner, which corner provokes both triangles, and a draw that spans the index pattern's chunks.
#include "gl/quad_indices.h"

#include <cstdint>
#include <string>
#include <vector>

#include "gl/gl_api.h"
#include "gl/objects.h"
#include "gl/shader_library.h"
#include "gl_fixture.h"

namespace tc::test {
namespace {

// Quads [first, first + count) drawn by tests/gl/shaders/test_quads.vert, each over a 2x2 pixel
// block of a quadsPerRow x rows grid: every pixel of a drawn quad must hold its index + 1 from the
// provoking corner's flat output, every other pixel 0. The range starts off a chunk boundary and
// runs across the next one (the pattern is 65,536 quads, gl/quad_indices.cpp), so the base vertex
// of each chunk of the multi-draw counts.
TEST_F(GlTest, quad_indices_draw_each_quad_once_with_its_corners_and_corner_2_provoking) {
    const int quadsPerRow = 384, rows = 184;
    const int width = 2 * quadsPerRow, height = 2 * rows;
    const std::size_t first = 7, count = 70000;
    ASSERT_LE(first + count, std::size_t(quadsPerRow) * rows);

    gl::Texture target = gl::makeTexture2D(GL_R32UI, width, height);
    gl::Framebuffer framebuffer = gl::makeFramebuffer({&target}, nullptr, "quad test target");
    gl::Program program =
        gl::compileProgram({{GL_VERTEX_SHADER, "test_quads.vert"}, {GL_FRAGMENT_SHADER, "test_quads.frag"}});
    glProgramUniform1ui(program.id(), glGetUniformLocation(program.id(), "uQuadsPerRow"), GLuint(quadsPerRow));
    glProgramUniform2f(program.id(), glGetUniformLocation(program.id(), "uTargetSize"), float(width), float(height));
    gl::VertexArray vao = gl::VertexArray::create();
    gl::QuadIndices quads = gl::QuadIndices::create();
    quads.attachTo(vao);

    const GLuint zero = 0;
    glClearTexImage(target.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(program.id());
    glBindVertexArray(vao.id());
    quads.draw(first, count);
    quads.draw(first + count, 0);  // an empty range draws nothing
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    std::vector<GLuint> pixels(std::size_t(width) * height, 0xDEADBEEFu);
    glGetTextureImage(target.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(pixels.size() * sizeof(GLuint)),
                      pixels.data());
    int wrong = 0;
    std::string firstWrong;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::size_t q = std::size_t(y / 2) * quadsPerRow + std::size_t(x / 2);
            const GLuint expected = q >= first && q < first + count ? GLuint(q + 1) : 0u;
            const GLuint got = pixels[std::size_t(y) * width + x];
            if (got == expected) continue;
            if (wrong++ == 0)
                firstWrong = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") of quad " +
                             std::to_string(q) + ": " + std::to_string(got) + ", expected " + std::to_string(expected);
        }
    EXPECT_EQ(wrong, 0) << "first: " << firstWrong;
}

}  // namespace
}  // namespace tc::test
