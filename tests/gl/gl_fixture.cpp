#include "gl_fixture.h"

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "core/error.h"
#include "gl/shader_library.h"
#include "test_shaders.h"

namespace tc::test {
namespace {

// Owns the shared context between the first and the last test. A gtest Environment rather than a
// function-local static so the context is destroyed before exit(), while libEGL and the driver
// are still fully alive.
class GlEnvironment : public ::testing::Environment {
public:
    void SetUp() override {
        try {
            gl::ContextConfig config;
            config.backend = testBackend();
            config.debug = true;  // GL errors in tests print where they happen
            m_context.emplace(gl::Context::create(config));
            const gl::ContextInfo& info = m_context->info();
            std::printf("GL tests: %s%s%s, %s, %s\n", info.backend.c_str(), info.device.empty() ? "" : " device ",
                        info.device.c_str(), info.renderer.c_str(), info.version.c_str());
        } catch (const Error& e) {
            m_error = e.what();
        }
    }
    void TearDown() override { m_context.reset(); }

    std::optional<gl::Context> m_context;
    std::string m_error;
};

GlEnvironment* g_environment = nullptr;

}  // namespace

gl::Backend testBackend() {
    const char* name = std::getenv("TUBECAST_TEST_BACKEND");
    return gl::parseBackend(name && *name ? name : "auto");
}

gl::Context* sharedContext() {
    if (!g_environment || !g_environment->m_context) {
        ADD_FAILURE() << "no shared GL context: "
                      << (g_environment ? g_environment->m_error : "environment not registered");
        return nullptr;
    }
    return &*g_environment->m_context;
}

void GlTest::SetUp() {
    gl::Context* context = sharedContext();
    if (!context) GTEST_FAIL() << "GL tests need a context";
    context->makeCurrent();
}

}  // namespace tc::test

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    tc::gl::ShaderLibrary::instance().addEmbedded(tc::test::testShaders());
    // gtest owns and deletes registered environments.
    tc::test::g_environment =
        static_cast<tc::test::GlEnvironment*>(::testing::AddGlobalTestEnvironment(new tc::test::GlEnvironment));
    return RUN_ALL_TESTS();
}
