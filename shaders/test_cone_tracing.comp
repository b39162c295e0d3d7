// Test harness for shaders/cone_tracing.glsl (tests/gl/density_volume_test.cpp): evaluates
// coneTracedOcclusion at each query point into an SSBO.
layout(local_size_x = 64) in;

#include "cone_tracing.glsl"

struct ConeQuery {
    vec4 position;  // xyz world position, w unused
    vec4 normal;    // xyz normal (normalised by coneTracedOcclusion), w unused
};

layout(std430, binding = 0) readonly buffer Queries
{
    ConeQuery queries[];
};

layout(std430, binding = 1) writeonly buffer Results
{
    float ao[];
};

uniform uint uCount;
uniform int uCones;
uniform float uAperture;  // full apex angle, radians
uniform float uMaxDistance;
uniform float uStrength;
uniform float uStartOffset;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= uCount)
        return;
    ao[i] = coneTracedOcclusion(queries[i].position.xyz, queries[i].normal.xyz, uCones, uAperture,
                                uMaxDistance, uStrength, uStartOffset);
}
