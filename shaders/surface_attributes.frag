// Once per pixel after the visibility pass: re-intersect the ray with the visible segment (the
// same function on the same inputs, so the same hit) and write linear albedo, outward world
// normal + view depth, and polyline id for shading and the AOVs.
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "line_buffers.glsl"
#include "frame_uniforms.glsl"
#include "visible_hit.glsl"

layout(binding = TEXTURE_VISIBILITY_SEGMENTS) uniform usampler2D uSegments;

const uint kNoSegment = 0xFFFFFFFFu;

layout(location = 0) out vec4 outAlbedo;       // linear RGB, straight alpha
layout(location = 1) out vec4 outNormalDepth;  // outward world normal, view depth (+inf: background)
layout(location = 2) out uint outId;           // polyline id

void main() {
    uint segment = texelFetch(uSegments, ivec2(gl_FragCoord.xy), 0).r;
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    float t;
    vec3 n;
    if (segment == kNoSegment || !visibleHit(ray, segmentCone(segment), t, n)) {
        outAlbedo = vec4(0.0);
        outNormalDepth = vec4(0.0, 0.0, 0.0, uintBitsToFloat(0x7F800000u));
        outId = kNoSegment;
        return;
    }
    uint v0 = segmentVertices[2u * segment];
    uint v1 = segmentVertices[2u * segment + 1u];
    vec3 a = positionRadius[v0].xyz, b = positionRadius[v1].xyz;
    vec3 p = ray.origin + t * ray.dir;
    vec3 axis = b - a;
    float len2 = dot(axis, axis);
    float s = len2 > 0.0 ? clamp(dot(p - a, axis) / len2, 0.0, 1.0) : 0.0;
    outAlbedo = mix(vertexColor[v0], vertexColor[v1], s);
    outNormalDepth = vec4(n, viewDepth(ray, t));
    outId = polylineId[v0];
}
