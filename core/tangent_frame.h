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

}  // namespace tc
