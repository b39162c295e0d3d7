// Test harness for shaders/cone_tracing.glsl (tests/gl/density_volume_test.cpp): evaluates
// coneTracedTubeOcclusion at each query point into an SSBO (own tube density 0: coneTracedOcclusion).
layout(local_size_x = 64) in;

#include "cone_tracing.glsl"

struct ConeQuery {
    vec4 position;  // xyz world position, w unused
    vec4 normal;    // xyz normal (normalised by coneTracedOcclusion), w unused
    vec4 ownOrigin; // ConeOwnTube: xyz origin, w density (0: none)
    vec4 ownDir;    // xyz unit axis, w unused
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
    ConeQuery q = queries[i];
    ConeOwnTube own = ConeOwnTube(q.ownOrigin.xyz, q.ownDir.xyz, q.ownOrigin.w);
    ao[i] = coneTracedTubeOcclusion(q.position.xyz, q.normal.xyz, own, uCones, uAperture, uMaxDistance, uStrength,
                                    uStartOffset);
}
