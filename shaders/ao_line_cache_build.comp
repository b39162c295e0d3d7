// Builds the cached line AO of shaders/ao_line_cache.glsl (layout there): one invocation per
// segment evaluates the exact cone traced AO (shaders/ambient_occlusion.glsl, compiled with
// AMBIENT_OCCLUSION, AO_LINES and AO_LINE_CACHE) at each of its samples and cached azimuths.
// gl::AoLineCache::build dispatches it in chunks of segments.
#include "ambient_occlusion.glsl"
#include "ao_line_cache.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = SSBO_AO_CACHE_OUT) writeonly buffer AoCacheOut { uint aoCacheOut[]; };

uniform uint uFirstSegment;
uniform uint uSegmentCount;

void main()
{
    uint segment = uFirstSegment + gl_GlobalInvocationID.x;
    if (segment >= uSegmentCount) return;
    vec4 a = positionRadius[segmentVertices[2u * segment]];
    vec4 b = positionRadius[segmentVertices[2u * segment + 1u]];
    vec3 axis;
    float unused;
    aoCacheSegmentAxis(a.xyz, b.xyz, a.xyz, axis, unused);
    uint first, count;
    bool joined;
    float origin;
    aoCacheSamples(segment, first, count, joined, origin);
    for (uint j = joined ? 1u : 0u; j < count; ++j) {  // a joined first sample is the previous one's
        float s = float(j) / float(count - 1u);
        vec4 c = mix(a, b, s);
        uint words[kAoCacheWords];
        for (uint w = 0u; w < kAoCacheWords; ++w) words[w] = 0u;
        for (int k = 0; k < kAoCacheAzimuths; ++k) {
            vec3 n = aoCacheNormal(axis, origin, k);
            float ao = exactLineAmbientOcclusion(segment, c.xyz + c.w * n, n);
            words[k >> 2] |= uint(round(clamp(ao, 0.0, 1.0) * 255.0)) << (8u * uint(k & 3));
        }
        for (uint w = 0u; w < kAoCacheWords; ++w) aoCacheOut[kAoCacheWords * (first + j) + w] = words[w];
    }
}
