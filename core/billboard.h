#pragma once
// The view-aligned billboard of one rounded cone: a screen-space quad, in NDC, that contains the
// cone's projected silhouette and is tight (Groß & Gumhold 2020, Sect. 5.1). The fragment shader
// ray casts the cone inside it; shaders/billboard.glsl is the GPU twin of this file (same math,
// same names, same edge cases; keep them in lock-step).
#include <array>
#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/rounded_cone.h"

namespace tc {

struct Billboard {
    std::array<glm::vec2, 4> ndc;  // corners in triangle-strip order (0,1,2 and 1,2,3 are the triangles)
    bool fullscreen;  // conservative fallback: the eye is in or next to the cone, or the cone crosses the eye plane
    bool culled;      // the cone lies entirely behind the eye plane: corners are a zero-area quad off screen
};

// For each end i the square x_i +- r'_i a_i +- r'_i b_i, where r'_i = |d_i| r_i / sqrt(|d_i|^2 - r_i^2)
// (d_i = eye - x_i) is the radius of the eye's tangent cone around sphere i in the plane through
// x_i perpendicular to d_i, and a_i (along the segment's projection), b_i are orthonormal and
// perpendicular to d_i. The square contains the tangent cone's cross-section, so its projection
// contains sphere i's; the cone is the convex hull of its spheres, so the rectangle aligned with
// the projected axis around the 8 projected corners contains the silhouette. Orthographic: d_i is
// -forward and r'_i = r_i. View along the axis: the rectangle is screen-axis aligned.
// viewProj maps world to OpenGL clip space (projectionMatrix * worldToCamera); eye and forward as
// Camera::eye / Camera::forward().
Billboard computeBillboard(const RoundedCone& cone, const glm::mat4& viewProj, const glm::vec3& eye, bool orthographic,
                           const glm::vec3& forward);
Billboard computeBillboard(const RoundedCone& cone, const glm::mat4& viewProj, const Camera& camera);

}  // namespace tc
