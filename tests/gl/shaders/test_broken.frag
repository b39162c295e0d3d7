// Test shader for tests/gl/shader_library_test.cpp: includes a chunk with a compile error.
layout(location = 0) out vec4 outColor;

#include "test_broken_chunk.glsl"

void main()
{
    outColor = brokenColor();
}
