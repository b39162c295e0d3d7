// Test shader for tests/gl/shader_library_test.cpp: fills an SSBO with fillValue(i).
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Output
{
    uint values[];
};

#include "test_fill_pattern.glsl"
// Deliberately included twice: the library includes each file once per stage, so this is a no-op
// (without that, fillValue would be redefined).
#include "test_fill_pattern.glsl"

uniform uint count;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i < count)
        values[i] = fillValue(i);
}
