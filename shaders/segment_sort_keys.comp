// Visibility-sort key pass (Groß & Gumhold 2020, Sect. 4.1): per segment S, the order-preserving
// uint key of its distance to the eye (perspective: point-segment distance; orthographic: minimum
// view depth) and the segment id S, the value the radix sort permutes. gl/sort_keys.h runs it.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer PositionRadius { vec4 positionRadius[]; };
layout(std430, binding = 1) readonly buffer SegmentVertices { uint segmentVertices[]; };
layout(std430, binding = 2) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = 3) writeonly buffer SegmentIds { uint segmentIds[]; };

#include "sort_keys.glsl"

uniform uint firstSegment;  // dispatches are split at the work group count limit
uniform uint segmentCount;
uniform vec3 eye;
uniform vec3 forward;       // unit view direction; used when orthographic
uniform bool orthographic;

void main()
{
    uint s = firstSegment + gl_GlobalInvocationID.x;
    if (s >= segmentCount)
        return;
    vec3 x0 = positionRadius[segmentVertices[2u * s]].xyz;
    vec3 x1 = positionRadius[segmentVertices[2u * s + 1u]].xyz;
    float d = orthographic ? segmentDepth(eye, forward, x0, x1) : segmentDistance(eye, x0, x1);
    keys[s] = sortKeyFromFloat(d);
    segmentIds[s] = s;
}
