// Headless contexts: both backends on this machine, exact readback, context info, error paths.
#include "gl/context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/error.h"
#include "gl/gl_api.h"
#include "gl/objects.h"
#include "gl_fixture.h"

namespace tc::test {
namespace {

// Tests that make contexts of their own. The shared context is made current again afterwards so
// tests in other files that do not derive from GlTest still find it current.
class SeparateContextTest : public ::testing::Test {
protected:
    void TearDown() override {
        if (gl::Context* shared = sharedContext()) shared->makeCurrent();
    }
};

gl::Context makeContext(gl::Backend backend) {
    gl::ContextConfig config;
    config.backend = backend;
    return gl::Context::create(config);
}

// Clears an RGBA8 framebuffer to a colour every 8-bit channel represents exactly and reads it back.
std::vector<unsigned char> clearAndReadBack(int width, int height) {
    gl::Texture color = gl::makeTexture2D(GL_RGBA8, width, height);
    gl::Framebuffer fb = gl::Framebuffer::create();
    glNamedFramebufferTexture(fb.id(), GL_COLOR_ATTACHMENT0, color.id(), 0);
    gl::checkFramebuffer(fb, "clear test");
    const float clear[4] = {51 / 255.f, 102 / 255.f, 153 / 255.f, 1.f};
    glClearNamedFramebufferfv(fb.id(), GL_COLOR, 0, clear);
    std::vector<unsigned char> pixels(static_cast<size_t>(width * height * 4), 0);
    glGetTextureImage(color.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(pixels.size()), pixels.data());
    return pixels;
}

void expectClearColor(const std::vector<unsigned char>& pixels) {
    ASSERT_FALSE(pixels.empty());
    for (size_t i = 0; i < pixels.size(); i += 4) {
        ASSERT_EQ(pixels[i + 0], 51) << "pixel " << i / 4;
        ASSERT_EQ(pixels[i + 1], 102) << "pixel " << i / 4;
        ASSERT_EQ(pixels[i + 2], 153) << "pixel " << i / 4;
        ASSERT_EQ(pixels[i + 3], 255) << "pixel " << i / 4;
    }
}

TEST_F(SeparateContextTest, egl_creates_a_4_5_core_llvmpipe_context_and_reads_back_a_clear_color) {
    gl::Context context = makeContext(gl::Backend::Egl);
    EXPECT_TRUE(context.info().backend == "egl-surfaceless" || context.info().backend == "egl-device")
        << context.info().backend;
    EXPECT_NE(context.info().version.find("4.5"), std::string::npos) << context.info().version;
    EXPECT_NE(context.info().version.find("Core Profile"), std::string::npos) << context.info().version;
    EXPECT_NE(context.info().renderer.find("llvmpipe"), std::string::npos) << context.info().renderer;
    EXPECT_TRUE(context.isSoftwareRenderer());
    expectClearColor(clearAndReadBack(13, 7));
}

TEST_F(SeparateContextTest, osmesa_creates_a_4_5_core_llvmpipe_context_and_reads_back_a_clear_color) {
    gl::Context context = makeContext(gl::Backend::OsMesa);
    EXPECT_EQ(context.info().backend, "osmesa");
    EXPECT_EQ(context.info().device, "");
    EXPECT_NE(context.info().version.find("4.5"), std::string::npos) << context.info().version;
    EXPECT_NE(context.info().renderer.find("llvmpipe"), std::string::npos) << context.info().renderer;
    EXPECT_TRUE(context.isSoftwareRenderer());
    expectClearColor(clearAndReadBack(13, 7));
}

TEST_F(SeparateContextTest, egl_and_osmesa_contexts_alternate_in_one_process) {
    for (int round = 0; round < 2; ++round) {
        {
            gl::Context egl = makeContext(gl::Backend::Egl);
            expectClearColor(clearAndReadBack(4, 4));
        }
        {
            gl::Context osmesa = makeContext(gl::Backend::OsMesa);
            expectClearColor(clearAndReadBack(4, 4));
        }
    }
    // Both alive at once, switching back and forth.
    gl::Context egl = makeContext(gl::Backend::Egl);
    gl::Context osmesa = makeContext(gl::Backend::OsMesa);
    egl.makeCurrent();
    expectClearColor(clearAndReadBack(4, 4));
    osmesa.makeCurrent();
    expectClearColor(clearAndReadBack(4, 4));
}

TEST_F(SeparateContextTest, moved_context_keeps_working_and_moved_from_is_empty) {
    gl::Context a = makeContext(gl::Backend::Egl);
    gl::Context b = std::move(a);
    EXPECT_EQ(b.info().backend.rfind("egl", 0), 0u);
    expectClearColor(clearAndReadBack(2, 2));
    EXPECT_THROW(a.info(), Error);  // NOLINT(bugprone-use-after-move): the empty state is the point
}

TEST_F(SeparateContextTest, egl_device_out_of_range_names_the_device_count) {
    gl::ContextConfig config;
    config.backend = gl::Backend::Egl;
    config.device = 99;
    try {
        gl::Context::create(config);
        FAIL() << "expected ContextError";
    } catch (const ContextError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("EGL backend failed"), std::string::npos) << message;
        EXPECT_NE(message.find("EGL device 99 does not exist; there are"), std::string::npos) << message;
    }
}

TEST_F(SeparateContextTest, device_index_implies_egl_and_is_rejected_for_osmesa) {
    gl::ContextConfig config;
    config.device = 99;
    EXPECT_THROW(gl::Context::create(config), ContextError) << "auto must not fall back to OSMesa";
    config.backend = gl::Backend::OsMesa;
    EXPECT_THROW(gl::Context::create(config), InputError);
}

TEST_F(SeparateContextTest, egl_device_zero_is_mesas_software_device_here) {
    gl::ContextConfig config;
    config.backend = gl::Backend::Egl;
    config.device = 0;
    gl::Context context = gl::Context::create(config);
    EXPECT_EQ(context.info().backend, "egl-device");
    EXPECT_EQ(context.info().device.rfind("0 (", 0), 0u) << context.info().device;
    if (!context.isSoftwareRenderer()) GTEST_SKIP() << "device 0 is hardware here";
    EXPECT_EQ(context.info().device, "0 (Mesa software device)");
    expectClearColor(clearAndReadBack(3, 3));
}

TEST_F(GlTest, shared_context_reads_back_a_clear_color) {
    expectClearColor(clearAndReadBack(16, 16));
}

TEST_F(GlTest, context_info_lists_the_pipeline_extensions_llvmpipe_has) {
    const gl::ContextInfo& info = context().info();
    if (info.renderer.find("llvmpipe") == std::string::npos)
        GTEST_SKIP() << "extension expectations are for llvmpipe, renderer is " << info.renderer;
    auto listed = [&](const std::string& name) {
        return std::find(info.extensions.begin(), info.extensions.end(), name) != info.extensions.end();
    };
    EXPECT_TRUE(listed("GL_ARB_gpu_shader_int64"));
    EXPECT_TRUE(listed("GL_KHR_debug"));
    EXPECT_FALSE(listed("GL_ARB_fragment_shader_interlock"));
    EXPECT_FALSE(listed("GL_ARB_shader_atomic_int64"));
    // hasExtension searches the full list, not just the pipeline's.
    EXPECT_TRUE(info.hasExtension("GL_ARB_compute_shader"));
    EXPECT_TRUE(info.hasExtension("GL_ARB_gpu_shader_int64"));
    EXPECT_FALSE(info.hasExtension("GL_ARB_fragment_shader_interlock"));
    EXPECT_FALSE(info.hasExtension("GL_ARB_gpu_shader_int6"));
    EXPECT_FALSE(info.vendor.empty());
    EXPECT_NE(info.glslVersion.find("4.50"), std::string::npos) << info.glslVersion;
}

TEST_F(GlTest, every_gl_4_5_entry_point_is_loaded) {
    const gl::GlFunctionCount count = gl::glFunctionCount();
    EXPECT_GT(count.known, 600);
    EXPECT_GE(count.loaded, count.known - 40);  // only 4.6 additions may be missing
}

TEST(ParseBackend, accepts_the_three_backend_names) {
    EXPECT_EQ(gl::parseBackend("auto"), gl::Backend::Auto);
    EXPECT_EQ(gl::parseBackend("egl"), gl::Backend::Egl);
    EXPECT_EQ(gl::parseBackend("osmesa"), gl::Backend::OsMesa);
}

TEST(ParseBackend, rejects_vulkan_naming_the_valid_values) {
    try {
        gl::parseBackend("vulkan");
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "--backend: expected one of auto, egl, osmesa, got 'vulkan'");
        EXPECT_EQ(e.code(), ExitCode::InvalidInput);
    }
}

TEST_F(SeparateContextTest, force_no_gl_env_gives_context_error_for_every_backend) {
    ::setenv("TUBECAST_FORCE_NO_GL", "1", 1);
    for (gl::Backend backend : {gl::Backend::Auto, gl::Backend::Egl, gl::Backend::OsMesa}) {
        try {
            makeContext(backend);
            ADD_FAILURE() << "expected ContextError";
        } catch (const ContextError& e) {
            EXPECT_EQ(e.code(), ExitCode::NoGpuContext);
            EXPECT_NE(std::string(e.what()).find("TUBECAST_FORCE_NO_GL"), std::string::npos) << e.what();
        }
    }
    ::unsetenv("TUBECAST_FORCE_NO_GL");
}

TEST(ContextWithoutEglDrivers, egl_fails_with_a_context_error_and_auto_falls_back_to_osmesa) {
    // glvnd reads its vendor list once per process, so the check runs in a child: the
    // "threadsafe" death-test style re-executes this binary, which inherits the environment.
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    ::setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/egl_vendor.json", 1);
    EXPECT_EXIT(
        {
            try {
                makeContext(gl::Backend::Egl);
                std::fprintf(stderr, "EGL unexpectedly worked\n");
                std::exit(1);
            } catch (const ContextError& e) {
                std::fprintf(stderr, "%s\n", e.what());
            }
            gl::Context context = makeContext(gl::Backend::Auto);
            std::fprintf(stderr, "auto: %s\n", context.info().backend.c_str());
            std::exit(0);
        },
        ::testing::ExitedWithCode(0), "EGL backend failed: .*use --backend osmesa(.|\n)*auto: osmesa");
    ::unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
}

}  // namespace
}  // namespace tc::test
