// Visibility-sort key pass (Groß & Gumhold 2020, Sect. 4.1): per segment S, the order-preserving
// uint key of its distance to the eye (perspective: point-segment distance; orthographic: minimum
// view depth) and the segment id S, the value the radix sort permutes. gl/sort_keys.h runs it.
layout(local_size_x = 64) in;

layout(std430, binding = SSBO_SORT_POSITION_RADIUS) readonly buffer PositionRadius { vec4 positionRadius[]; };
layout(std430, binding = SSBO_SORT_SEGMENT_VERTICES) readonly buffer SegmentVertices { uint segmentVertices[]; };
layout(std430, binding = SSBO_SORT_KEYS) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = SSBO_SORT_SEGMENT_IDS) writeonly buffer SegmentIds { uint segmentIds[]; };
layout(std430, binding = SSBO_SORT_OUTSIDE_COUNT) buffer OutsideCount { uint outside; };

#include "sort_keys.glsl"

uniform uint firstSegment;  // dispatches are split at the work group count limit
uniform uint segmentCount;
uniform vec3 eye;
uniform vec3 forward;       // unit view direction; used when orthographic
uniform bool orthographic;
uniform bool frustumTest;
uniform vec4 frustumPlanes[5];  // inward unit normal, offset (core/frustum.h)

shared uint groupOutside;

void main()
{
    if (gl_LocalInvocationIndex == 0u)
        groupOutside = 0u;
    barrier();
    uint s = firstSegment + gl_GlobalInvocationID.x;
    if (s < segmentCount) {
        vec4 a = positionRadius[segmentVertices[2u * s]];
        vec4 b = positionRadius[segmentVertices[2u * s + 1u]];
        float d = orthographic ? segmentDepth(eye, forward, a.xyz, b.xyz) : segmentDistance(eye, a.xyz, b.xyz);
        uint key = sortKeyFromFloat(d);
        if (frustumTest) {
            // The segment's rounded cone lies in this sphere.
            vec3 centre = 0.5 * (a.xyz + b.xyz);
            float radius = 0.5 * length(b.xyz - a.xyz) + max(a.w, b.w);
            bool out_ = false;
            for (int i = 0; i < 5; ++i)
                out_ = out_ || dot(frustumPlanes[i].xyz, centre) + frustumPlanes[i].w < -radius;
            if (out_) {
                key = 0xFFFFFFFFu;
                atomicAdd(groupOutside, 1u);
            }
        }
        keys[s] = key;
        segmentIds[s] = s;
    }
    // One global atomic per work group instead of one per segment.
    barrier();
    if (gl_LocalInvocationIndex == 0u && groupOutside != 0u)
        atomicAdd(outside, groupOutside);
}
