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

// render.billboard_shape.
//
// Gross2020: the paper's quad (Sect. 5.1, Eq. 1-10). With r0 <= r1 (else the ends are swapped),
// u = d x d0 / |d x d0| is normal to the plane through the eye and the axis, v_i = u x d_i / |..|
// (d = x1 - x0, d_i = eye - x_i). p_0,1 = x0 +- r'0 v0, p_2,3 = x1 +- r'1 v1 with the eye's
// tangent-cone radius r'_i = |d_i| s_i, s_i = r_i / sqrt(|d_i|^2 - r_i^2) (Eq. 2-4) are silhouette
// points; the outermost of p0 / p2 and of p1 / p3 seen from the eye (the angle with w = u x view,
// Eq. 6-9) give the two end edges, which lie in tangent planes of their spheres; the corners are
// those points +- r''_i u with r''_i = |d_i| max(s0, s1) (Eq. 5, 10). Orthographic: d_i = -forward,
// s_i = r_i and r''_i = max(r0, r1). Viewed (nearly) along the axis, d x d0 vanishes and the quad
// is the Rectangle below.
//
// Rectangle: for each end i the square x_i +- r'_i a_i +- r'_i b_i (a_i along the segment's
// projection, b_i, both perpendicular to d_i) contains the tangent cone's cross-section, so its
// projection contains sphere i's; the cone is the convex hull of its spheres, so the rectangle
// aligned with the projected axis around the 8 projected corners contains the silhouette. About
// 1.5x the projected hull's area on average (tests/unit/billboard_test.cpp), more than Gross2020:
// kept as the reference the paper's quad is measured against (docs/performance.md).
enum class BillboardShape { Gross2020, Rectangle };

struct Billboard {
    std::array<glm::vec2, 4> ndc;  // corners in triangle-strip order (0,1,2 and 1,2,3 are the triangles)
    bool fullscreen;  // conservative fallback: the eye is in or next to the cone, or the cone crosses the eye plane
    bool culled;      // the cone lies entirely behind the eye plane: corners are a zero-area quad off screen
};

// viewProj maps world to OpenGL clip space (projectionMatrix * worldToCamera); eye and forward as
// Camera::eye / Camera::forward(). Both shapes are padded outward by a relative 1e-5 of their
// extent (+1e-6 NDC) for rounding in the projection and in the rasteriser's edge tests.
Billboard computeBillboard(const RoundedCone& cone, const glm::mat4& viewProj, const glm::vec3& eye, bool orthographic,
                           const glm::vec3& forward, BillboardShape shape = BillboardShape::Gross2020);
Billboard computeBillboard(const RoundedCone& cone, const glm::mat4& viewProj, const Camera& camera,
                           BillboardShape shape = BillboardShape::Gross2020);

}  // namespace tc
