// The frame uniform block: shaders/frame_uniforms.glsl and its C++ twin gl::FrameUniforms
// (gl/frame_uniforms.h) declare one std140 layout twice; these tests keep the two in step.
#include "gl/frame_uniforms.h"

#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "gl/bindings.h"
#include "gl/gl_api.h"
#include "gl/objects.h"
#include "gl/shader_library.h"
#include "gl_fixture.h"

namespace tc::test {
namespace {

using gl::FrameUniforms;

struct Member {
    const char* glslName;
    std::size_t cppOffset;
};

// Every member of the block with its C++ counterpart.
const std::vector<Member>& members() {
    static const std::vector<Member> all = {
        {"uViewProj", offsetof(FrameUniforms, viewProj)},
        {"uEye", offsetof(FrameUniforms, eye)},
        {"uTanHalfFov", offsetof(FrameUniforms, tanHalfFov)},
        {"uForward", offsetof(FrameUniforms, forward)},
        {"uOrthoHalfHeight", offsetof(FrameUniforms, orthoHalfHeight)},
        {"uRight", offsetof(FrameUniforms, right)},
        {"uFarDepth", offsetof(FrameUniforms, farDepth)},
        {"uUp", offsetof(FrameUniforms, up)},
        {"uOrthographic", offsetof(FrameUniforms, orthographic)},
        {"uLightDir", offsetof(FrameUniforms, lightDir)},
        {"uCapClipping", offsetof(FrameUniforms, capClipping)},
        {"uLightTerms", offsetof(FrameUniforms, lightTerms)},
        {"uNdcToTarget", offsetof(FrameUniforms, ndcToTarget)},
        {"uViewport", offsetof(FrameUniforms, viewport)},
        {"uPixelOffset", offsetof(FrameUniforms, pixelOffset)},
        {"uTargetSize", offsetof(FrameUniforms, targetSize)},
        {"uRegionLo", offsetof(FrameUniforms, regionLo)},
        {"uRegionHi", offsetof(FrameUniforms, regionHi)},
        {"uRayBase", offsetof(FrameUniforms, rayBase)},
        {"uRayDx", offsetof(FrameUniforms, rayDx)},
        {"uRayDy", offsetof(FrameUniforms, rayDy)},
    };
    return all;
}

GLint resourceProperty(GLuint program, GLenum interface, GLuint index, GLenum property) {
    GLint value = -1;
    glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
    return value;
}

TEST_F(GlTest, frame_uniform_block_has_the_offsets_size_and_binding_of_the_cpp_struct) {
    const gl::Program program = gl::compileProgram({{GL_COMPUTE_SHADER, "test_frame_uniforms.comp"}});
    const GLuint p = program.id();
    const GLuint block = glGetProgramResourceIndex(p, GL_UNIFORM_BLOCK, "FrameUniforms");
    ASSERT_NE(block, GL_INVALID_INDEX);
    EXPECT_EQ(resourceProperty(p, GL_UNIFORM_BLOCK, block, GL_BUFFER_DATA_SIZE), GLint(sizeof(FrameUniforms)));
    EXPECT_EQ(resourceProperty(p, GL_UNIFORM_BLOCK, block, GL_BUFFER_BINDING), GLint(gl::binding::kFrameUniforms));
    // No GLSL member without a C++ one.
    EXPECT_EQ(resourceProperty(p, GL_UNIFORM_BLOCK, block, GL_NUM_ACTIVE_VARIABLES), GLint(members().size()));
    for (const Member& m : members()) {
        SCOPED_TRACE(m.glslName);
        const GLuint index = glGetProgramResourceIndex(p, GL_UNIFORM, m.glslName);
        ASSERT_NE(index, GL_INVALID_INDEX);
        EXPECT_EQ(resourceProperty(p, GL_UNIFORM, index, GL_BLOCK_INDEX), GLint(block));
        EXPECT_EQ(resourceProperty(p, GL_UNIFORM, index, GL_OFFSET), GLint(m.cppOffset));
    }
}

TEST_F(GlTest, frame_uniform_block_reads_every_member_as_the_cpp_struct_wrote_it) {
    // Distinct values in every word, bools true, so a swapped or shifted member shows.
    FrameUniforms u;
    std::vector<float> values(72);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.5f + float(i) * 1.25f;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) u.viewProj[c][r] = values[std::size_t(4 * c + r)];
    u.eye = {values[16], values[17], values[18]};
    u.tanHalfFov = values[19];
    u.forward = {values[20], values[21], values[22]};
    u.orthoHalfHeight = values[23];
    u.right = {values[24], values[25], values[26]};
    u.farDepth = values[27];
    u.up = {values[28], values[29], values[30]};
    u.orthographic = 1;
    u.lightDir = {values[32], values[33], values[34]};
    u.capClipping = 1;
    u.lightTerms = {values[36], values[37], values[38], values[39]};
    u.ndcToTarget = {values[40], values[41], values[42], values[43]};
    u.viewport = {values[44], values[45]};
    u.pixelOffset = {values[46], values[47]};
    u.targetSize = {values[48], values[49]};
    u.regionLo = {values[52], values[53], values[54], values[55]};
    u.regionHi = {values[56], values[57], values[58], values[59]};
    u.rayBase = {values[60], values[61], values[62], values[63]};
    u.rayDx = {values[64], values[65], values[66], values[67]};
    u.rayDy = {values[68], values[69], values[70], values[71]};

    const gl::Program program = gl::compileProgram({{GL_COMPUTE_SHADER, "test_frame_uniforms.comp"}});
    gl::Buffer uniforms;
    gl::uploadFrameUniforms(uniforms, u);
    const std::size_t used = offsetof(FrameUniforms, rayDy) + sizeof u.rayDy;
    gl::Buffer out = gl::makeBuffer(used, nullptr, 0);
    glUseProgram(program.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, out.id());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
    std::vector<unsigned char> read(used, 0xAB);
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(used), read.data());
    const auto* written = reinterpret_cast<const unsigned char*>(&u);
    for (std::size_t word = 0; word < used / 4; ++word)
        EXPECT_EQ(std::memcmp(&read[4 * word], written + 4 * word, 4), 0) << "word " << word;
}

}  // namespace
}  // namespace tc::test
