// The visible surface of one segment along a ray for the opaque path: the entry point, or the
// exit point when the ray starts inside the tube (the eye inside a tube sees the inner wall).
// tc::renderReferenceOpaque applies the same rule. GLSL 4.50 chunk, after rounded_cone.glsl and
// line_buffers.glsl.
#include "frame_uniforms.glsl"

// axis: coneAxis(cone) (rounded_cone.glsl).
bool visibleHit(Ray ray, RoundedCone cone, vec4 axis, out float t, out vec3 n) {
    ConeInterval hit = intersectRoundedCone(ray, cone, axis);
    t = 0.0;
    n = vec3(0.0);
    if (!hit.hit) return false;
    if (hit.tIn > 0.0) {
        t = hit.tIn;
        n = hit.nIn;
        return true;
    }
    if (hit.tOut > 0.0) {
        t = hit.tOut;
        n = hit.nOut;
        return true;
    }
    return false;
}

RoundedCone segmentCone(uint segment) {
    vec4 a = positionRadius[segmentVertices[2u * segment]];
    vec4 b = positionRadius[segmentVertices[2u * segment + 1u]];
    return RoundedCone(a.xyz, a.w, b.xyz, b.w);
}

// What the visibility pass (rounded_cone_gbuffer.frag) stores for `cone` along `ray` as
// gl_FragDepth, the value its depth test compares: view depth / uFarDepth. False where it writes
// no fragment. The surface attributes pass recomputes it with this same function to resolve ties.
bool visibleFragmentDepth(Ray ray, RoundedCone cone, vec4 axis, out float t, out vec3 n, out float fragDepth) {
    fragDepth = 1.0;
    if (!visibleHit(ray, cone, axis, t, n)) return false;
    float depth = viewDepth(ray, t);
    if (depth <= 0.0) return false;
    fragDepth = clamp(depth / uFarDepth, 0.0, 1.0);
    return true;
}

bool visibleFragmentDepth(Ray ray, RoundedCone cone, out float t, out vec3 n, out float fragDepth) {
    return visibleFragmentDepth(ray, cone, coneAxis(cone), t, n, fragDepth);
}
