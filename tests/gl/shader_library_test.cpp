// The shader library: include expansion, #line mapping of compile errors, defines, overrides.
#include "gl/shader_library.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "gl/gl_api.h"
#include "gl/gpu_timer.h"
#include "gl/objects.h"
#include "gl_fixture.h"

namespace tc::test {
namespace {

std::string compileError(std::initializer_list<std::pair<GLenum, std::string_view>> stages,
                         const std::vector<std::string>& defines = {}) {
    try {
        gl::compileProgram(stages, defines);
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::Internal);
        return e.what();
    }
    ADD_FAILURE() << "expected a compile error";
    return {};
}

// Runs shaders/test_fill.comp over `count` entries and returns the SSBO.
std::vector<GLuint> runFill(const std::vector<std::string>& defines, GLuint count) {
    gl::Program program = gl::compileProgram({{GL_COMPUTE_SHADER, "test_fill.comp"}}, defines);
    gl::Buffer buffer = gl::makeBuffer(count * sizeof(GLuint), nullptr, 0);
    glProgramUniform1ui(program.id(), glGetUniformLocation(program.id(), "count"), count);
    glUseProgram(program.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer.id());
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<GLuint> values(count, 0xFFFFFFFFu);
    glGetNamedBufferSubData(buffer.id(), 0, count * sizeof(GLuint), values.data());
    glUseProgram(0);
    return values;
}

// Points the library at a temporary directory for one test and restores it afterwards.
class ShaderOverrideTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        m_dir = std::filesystem::path(TUBECAST_TEST_TMP) / "shader_override";
        std::filesystem::remove_all(m_dir);
        std::filesystem::create_directories(m_dir);
        gl::ShaderLibrary::instance().setOverrideDir(m_dir.string());
    }
    void TearDown() override { gl::ShaderLibrary::instance().setOverrideDir(""); }
    void write(const std::string& name, const std::string& text) { std::ofstream(m_dir / name) << text; }
    std::filesystem::path m_dir;
};

TEST_F(GlTest, compile_error_in_an_included_chunk_names_the_chunk_and_its_line) {
    const std::string message = compileError({{GL_FRAGMENT_SHADER, "test_broken.frag"}});
    EXPECT_NE(message.find("compiling fragment shader shaders/test_broken.frag failed"), std::string::npos) << message;
    // test_broken_chunk.glsl line 6 uses an undeclared identifier.
    EXPECT_NE(message.find("shaders/test_broken_chunk.glsl:6:"), std::string::npos) << message;
    EXPECT_NE(message.find("undeclared_identifier"), std::string::npos) << message;
    EXPECT_EQ(message.find("\n0:"), std::string::npos) << "unmapped location left: " << message;
}

TEST_F(GlTest, compute_shader_fills_an_ssbo_with_the_pattern_its_defines_select) {
    const GLuint count = 1000;  // not a multiple of the work group size
    std::vector<GLuint> linear = runFill({"FILL_OFFSET 7"}, count);
    for (GLuint i = 0; i < count; ++i) ASSERT_EQ(linear[i], 3 * i + 7) << "index " << i;

    std::vector<GLuint> square = runFill({"FILL_OFFSET 11", "FILL_SQUARE"}, count);
    for (GLuint i = 0; i < count; ++i) ASSERT_EQ(square[i], i * i + 11) << "index " << i;
}

TEST_F(GlTest, missing_define_reaches_the_shaders_error_directive) {
    const std::string message = compileError({{GL_COMPUTE_SHADER, "test_fill.comp"}});
    EXPECT_NE(message.find("shaders/test_fill_pattern.glsl:4:"), std::string::npos) << message;
    EXPECT_NE(message.find("FILL_OFFSET must be defined"), std::string::npos) << message;
}

TEST(ShaderExpansion, numbers_files_in_inclusion_order_and_includes_each_once) {
    const gl::ExpandedShader expanded = gl::expandShader("test_fill.comp", {"FILL_OFFSET 1", "A"});
    ASSERT_EQ(expanded.files.size(), 3u);
    EXPECT_EQ(expanded.files[0], "<preamble>");
    EXPECT_EQ(expanded.files[1], "shaders/test_fill.comp");
    EXPECT_EQ(expanded.files[2], "shaders/test_fill_pattern.glsl");
    EXPECT_EQ(expanded.text.rfind("#version 450 core\n#define FILL_OFFSET 1\n#define A\n#line 100001 1\n", 0), 0u)
        << expanded.text;
    size_t functions = 0;
    for (size_t at = 0; (at = expanded.text.find("uint fillValue", at)) != std::string::npos; ++at) ++functions;
    EXPECT_EQ(functions, 1u) << "the second #include must be dropped";
}

TEST(ShaderExpansion, rejects_a_malformed_define) {
    EXPECT_THROW(gl::expandShader("test_fill.comp", {"1BAD"}), Error);
    EXPECT_THROW(gl::expandShader("test_fill.comp", {""}), Error);
}

TEST(ShaderExpansion, unknown_file_names_itself) {
    try {
        gl::ShaderLibrary::instance().source("no_such_shader.glsl");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'no_such_shader.glsl' is not embedded"), std::string::npos) << e.what();
    }
}

TEST(ShaderLog, rewrites_mesa_nvidia_and_plain_locations) {
    const std::vector<std::string> files = {"<preamble>", "shaders/a.frag", "shaders/b.glsl"};
    EXPECT_EQ(gl::rewriteShaderLog("0:2(3): error: x\n", files), "<preamble>:2:3: error: x\n");
    EXPECT_EQ(gl::rewriteShaderLog("2:200005(10): error: y\n", files), "shaders/b.glsl:5:10: error: y\n");
    // Mesa reports source string 0 for some errors; the line still says which file.
    EXPECT_EQ(gl::rewriteShaderLog("0:200005(10): error: y\n", files), "shaders/b.glsl:5:10: error: y\n");
    EXPECT_EQ(gl::rewriteShaderLog("1(100007) : error C0000: z\n", files), "shaders/a.frag:7: error C0000: z\n");
    EXPECT_EQ(gl::rewriteShaderLog("ERROR: 2:200009: w\n", files), "ERROR: shaders/b.glsl:9: w\n");
    EXPECT_EQ(gl::rewriteShaderLog("9:1(1): error: v\nplain text\n", files), "9:1:1: error: v\nplain text\n");
}

TEST_F(ShaderOverrideTest, override_dir_wins_and_errors_after_an_include_keep_the_including_files_line) {
    // Line 5 of the override file, after an include of the embedded pattern chunk.
    write("test_override.comp",
          "layout(local_size_x = 1) in;\n"
          "#define FILL_OFFSET 0\n"
          "#include \"test_fill_pattern.glsl\"\n"
          "void main() {\n"
          "    uint x = fillValue(1u) + not_declared;\n"
          "}\n");
    const std::string message = compileError({{GL_COMPUTE_SHADER, "test_override.comp"}});
    const std::string path = (m_dir / "test_override.comp").string();
    EXPECT_NE(message.find(path + ":5:"), std::string::npos) << message;

    // A file in the override directory replaces the embedded one of the same name.
    write("test_fill_pattern.glsl", "uint fillValue(uint i) { return 42u; }\n");
    std::vector<GLuint> values = runFill({}, 5);
    for (GLuint v : values) EXPECT_EQ(v, 42u);
}

TEST(ShaderLibrary, override_dir_that_is_not_a_directory_is_an_input_error) {
    EXPECT_THROW(gl::ShaderLibrary::instance().setOverrideDir("/nonexistent/shaders"), InputError);
    EXPECT_EQ(gl::ShaderLibrary::instance().overrideDir(), "");
}

TEST_F(GlTest, stage_timer_reports_stages_in_order_with_items_and_reuses_queries) {
    gl::StageTimer timer;
    for (int frame = 0; frame < 2; ++frame) {
        timer.begin("fill");
        runFill({"FILL_OFFSET 0"}, 4096);
        timer.setItems(4096);
        timer.end();
        timer.begin("empty");
        timer.end();
        const std::vector<tc::StageTime> times = timer.collect();
        ASSERT_EQ(times.size(), 2u);
        EXPECT_EQ(times[0].stage, "fill");
        EXPECT_EQ(times[0].items, 4096u);
        EXPECT_GE(times[0].gpuMs, 0.0);
        EXPECT_GT(times[0].cpuMs, 0.0);
        EXPECT_EQ(times[1].stage, "empty");
        EXPECT_EQ(times[1].items, 0u);
    }
    timer.begin("open");
    EXPECT_THROW(timer.begin("nested"), Error);
    EXPECT_THROW(timer.collect(), Error);
    timer.end();
    EXPECT_EQ(timer.collect().size(), 1u);
}

TEST_F(GlTest, objects_are_move_only_owners_with_an_empty_state) {
    static_assert(!std::is_copy_constructible_v<gl::Buffer>);
    static_assert(std::is_nothrow_move_constructible_v<gl::Texture>);
    static_assert(std::is_nothrow_move_assignable_v<gl::Program>);
    gl::Buffer empty;
    EXPECT_TRUE(empty.empty());
    EXPECT_FALSE(empty);

    gl::Buffer a = gl::makeBuffer(16, nullptr, GL_DYNAMIC_STORAGE_BIT);
    const GLuint id = a.id();
    EXPECT_TRUE(glIsBuffer(id));
    gl::Buffer b = std::move(a);
    EXPECT_EQ(b.id(), id);
    EXPECT_TRUE(a.empty());  // NOLINT(bugprone-use-after-move)
    b = gl::Buffer();
    EXPECT_FALSE(glIsBuffer(id)) << "move-assigning over an owner deletes its object";

    gl::Buffer zero = gl::makeBuffer(0, nullptr, 0);  // zero bytes is allowed
    GLint64 size = 0;
    glGetNamedBufferParameteri64v(zero.id(), GL_BUFFER_SIZE, &size);
    EXPECT_GT(size, 0);

    gl::Framebuffer fb = gl::Framebuffer::create();
    try {
        gl::checkFramebuffer(fb, "no attachments");
        FAIL() << "expected an incomplete framebuffer";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(),
                     "framebuffer 'no attachments' is incomplete: "
                     "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT");
    }
}

TEST_F(GlTest, debug_context_prints_gl_errors_to_stderr) {
    ::testing::internal::CaptureStderr();
    glBindBuffer(0xDEAD, 0);  // GL_INVALID_ENUM
    const std::string log = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(log.find("gl-debug: error (high"), std::string::npos) << log;
}

}  // namespace
}  // namespace tc::test
