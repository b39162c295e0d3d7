#pragma once
// One headless GL context shared by every test of the GL test binary (tests/gl/).
//
// The context is made once per process, before the first test, with the backend named by the
// environment variable TUBECAST_TEST_BACKEND ("auto" by default, or "egl" / "osmesa"), so the
// whole suite can be run against each backend. GL tests derive their fixture from GlTest:
//     TEST_F(GlTest, kbuffer_matches_depth_peeling_when_k_exceeds_depth_complexity) { ... }
#include <gtest/gtest.h>

#include "gl/context.h"

namespace tc::test {

// The backend the shared context was asked for (TUBECAST_TEST_BACKEND).
gl::Backend testBackend();

// The shared context. Fails the calling test (and returns null) if it could not be created.
gl::Context* sharedContext();

// Makes the shared context current before each test, so a test that made contexts of its own
// (context_test.cpp) cannot leave the next one without a context. Fails the test if there is none.
class GlTest : public ::testing::Test {
protected:
    void SetUp() override;
    gl::Context& context() { return *sharedContext(); }
};

}  // namespace tc::test
