#pragma once
// An orthonormal tangent frame around a unit vector without branches on its direction (Duff et
// al. 2017, "Building an Orthonormal Basis, Revisited"): the CPU twin of coneTangentFrame in
// shaders/cone_tracing.glsl, same operations, so CPU cone tracing and the AO cache place their
// cones exactly where the shaders do.
#include <glm/glm.hpp>

namespace tc {

inline void tangentFrame(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
    const float s = n.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (s + n.z);
    const float c = n.x * n.y * a;
    t = glm::vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    b = glm::vec3(c, s + n.y * n.y * a, -n.y);
}

// The tangent a rotation-minimising frame carries into a segment of unit `axis` whose own frame
// tangent is `t`: `previous` (the tangent carried out of the segment before it on the polyline, 0
// where the polyline starts) projected on the plane across `axis` and normalised, or `t` where
// nothing is carried or the projection nearly vanishes (a fold). The AO line cache's azimuth
// origin (gl/ao_line_cache.h) and incomingTangents (core/kd_decomposition.h) both call this, so a
// polyline cut into runs carries the same frame bit for bit.
inline glm::vec3 transportTangent(const glm::vec3& previous, const glm::vec3& axis, const glm::vec3& t) {
    const glm::vec3 across = previous - glm::dot(previous, axis) * axis;
    const float acrossLength = glm::length(across);
    return acrossLength > 1e-3f ? across / acrossLength : t;
}

// The unit axis of segment (a, b) as the AO cache frames it: z for a zero-length segment.
inline glm::vec3 segmentAxis(const glm::vec3& a, const glm::vec3& b) {
    const float length = glm::length(b - a);
    return length > 0.0f ? (b - a) / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace tc
