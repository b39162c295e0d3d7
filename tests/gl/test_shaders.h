#pragma once
// Shaders only the GL tests compile (tests/gl/shaders/), embedded into the test binary alone by
// tests/CMakeLists.txt and registered with the shader library before the first test
// (gl_fixture.cpp), so the tubecast binary does not carry them.
#include "gl/embedded_shaders.h"

namespace tc::test {

const std::vector<gl::EmbeddedShader>& testShaders();

}  // namespace tc::test
