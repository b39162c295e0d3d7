// G-buffer pass of the opaque path: ray-cast the segment's rounded cone, write the true depth.
// The first surface along the ray in front of the eye is the visible one: the entry point, or
// the exit point when the eye is inside the tube (tc::renderReferenceOpaque does the same).
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "line_buffers.glsl"
#include "frame_uniforms.glsl"

uniform float uFarDepth;  // gl_FragDepth = view depth / uFarDepth (linear, float depth buffer)

flat in uint vSegment;

layout(location = 0) out vec4 outAlbedo;       // linear RGB, straight alpha
layout(location = 1) out vec4 outNormalDepth;  // outward world normal, view depth
layout(location = 2) out uint outId;           // polyline id

void main() {
    uint v0 = segmentVertices[2u * vSegment];
    uint v1 = segmentVertices[2u * vSegment + 1u];
    vec4 a = positionRadius[v0];
    vec4 b = positionRadius[v1];
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    ConeInterval hit = intersectRoundedCone(ray, RoundedCone(a.xyz, a.w, b.xyz, b.w));
    if (!hit.hit) discard;
    float t;
    vec3 n;
    if (hit.tIn > 0.0) {
        t = hit.tIn;
        n = hit.nIn;
    } else if (hit.tOut > 0.0) {
        t = hit.tOut;
        n = hit.nOut;
    } else {
        discard;
    }
    float depth = viewDepth(ray, t);
    if (depth <= 0.0) discard;

    vec3 p = ray.origin + t * ray.dir;
    vec3 axis = b.xyz - a.xyz;
    float len2 = dot(axis, axis);
    float s = len2 > 0.0 ? clamp(dot(p - a.xyz, axis) / len2, 0.0, 1.0) : 0.0;
    outAlbedo = mix(vertexColor[v0], vertexColor[v1], s);
    outNormalDepth = vec4(n, depth);
    outId = polylineId[v0];
    gl_FragDepth = clamp(depth / uFarDepth, 0.0, 1.0);
}
