// Test chunk for tests/gl/shader_library_test.cpp: the error on line 6 (an undeclared
// identifier) must be reported as test_broken_chunk.glsl:6.
vec4 brokenColor()
{
    vec4 c = vec4(1.0);
    return c * undeclared_identifier;
}
