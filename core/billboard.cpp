#include "core/billboard.h"

#include <cmath>

namespace tc {
namespace {

constexpr std::array<glm::vec2, 4> kFullscreen = {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(-1, 1),
                                                  glm::vec2(1, 1)};
// Zero area and off screen: rasterises nothing.
constexpr std::array<glm::vec2, 4> kCulled = {glm::vec2(-2, -2), glm::vec2(-2, -2), glm::vec2(-2, -2),
                                              glm::vec2(-2, -2)};

// A unit vector perpendicular to v (unit).
glm::vec3 anyPerpendicular(glm::vec3 v) {
    glm::vec3 a = std::abs(v.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    return glm::normalize(glm::cross(v, a));
}

}  // namespace

Billboard computeBillboard(const RoundedCone& c, const glm::mat4& viewProj, const glm::vec3& eye, bool orthographic,
                           const glm::vec3& forward) {
    Billboard bb{kFullscreen, true, false};
    float d0 = glm::dot(c.x0 - eye, forward), d1 = glm::dot(c.x1 - eye, forward);
    // Rays start on the eye plane and go forward: nothing at view depth <= 0 is visible.
    if (glm::max(d0 + c.r0, d1 + c.r1) <= 0.0f) return {kCulled, false, true};

    float rmax = glm::max(c.r0, c.r1);
    if (!orthographic) {
        // Eye in (or within a hair of) the cone, or the cone reaching the eye plane: the
        // projection is unbounded or wraps around; cover the screen.
        if (sdRoundedCone(eye, c) <= 1e-4f * rmax) return bb;
        if (glm::min(d0 - c.r0, d1 - c.r1) <= 1e-6f * rmax) return bb;
    }

    glm::vec3 ba = c.x1 - c.x0;
    glm::vec3 x[2] = {c.x0, c.x1};
    float r[2] = {c.r0, c.r1};
    glm::vec2 pts[8];
    glm::vec2 centre[2];
    for (int i = 0; i < 2; ++i) {
        glm::vec3 di = eye - x[i];
        float D = glm::length(di);
        glm::vec3 v = orthographic ? -forward : di / D;
        float rp = r[i];
        if (!orthographic) {
            // Eq. of the tangent cone: D r / sqrt(D^2 - r^2); (D - r)(D + r) avoids cancellation.
            float k = (D - r[i]) * (D + r[i]);
            if (!(k > 1e-8f * D * D)) return bb;
            rp = D * r[i] / std::sqrt(k);
        }
        glm::vec3 a = ba - v * glm::dot(ba, v);
        float la = glm::length(a);
        a = la > 1e-6f * glm::length(ba) && la > 0.0f ? a / la : anyPerpendicular(v);
        glm::vec3 b = glm::cross(v, a);
        glm::vec4 cc = viewProj * glm::vec4(x[i], 1.0f);
        centre[i] = glm::vec2(cc) / cc.w;
        for (int k = 0; k < 4; ++k) {
            float sa = (k & 1) ? 1.0f : -1.0f, sb = (k & 2) ? 1.0f : -1.0f;
            glm::vec4 p = viewProj * glm::vec4(x[i] + (sa * rp) * a + (sb * rp) * b, 1.0f);
            // A square corner at or behind the eye plane (a sphere close to it): no finite quad.
            if (!(p.w > 1e-6f * cc.w)) return bb;
            pts[4 * i + k] = glm::vec2(p) / p.w;
        }
    }

    // Rectangle aligned with the projected axis; screen-axis aligned when viewed along the axis.
    glm::vec2 e = centre[1] - centre[0];
    float le = glm::length(e);
    float extent = glm::length(pts[0] - pts[3]) + glm::length(pts[4] - pts[7]);
    e = le > 1e-6f * extent && le > 0.0f ? e / le : glm::vec2(1, 0);
    glm::vec2 f(-e.y, e.x);
    float loE = 3.0e38f, hiE = -3.0e38f, loF = 3.0e38f, hiF = -3.0e38f;
    for (const glm::vec2& p : pts) {
        float pe = glm::dot(p, e), pf = glm::dot(p, f);
        loE = glm::min(loE, pe);
        hiE = glm::max(hiE, pe);
        loF = glm::min(loF, pf);
        hiF = glm::max(hiF, pf);
    }
    if (!(hiE - loE < 1e30f && hiF - loF < 1e30f)) return bb;  // overflow or NaN: stay conservative
    // Pad for rounding in the projection (relative) and in the rasteriser's edge tests.
    float padE = 1e-5f * (hiE - loE) + 1e-6f, padF = 1e-5f * (hiF - loF) + 1e-6f;
    loE -= padE;
    hiE += padE;
    loF -= padF;
    hiF += padF;
    bb.ndc = {loE * e + loF * f, hiE * e + loF * f, loE * e + hiF * f, hiE * e + hiF * f};
    bb.fullscreen = false;
    return bb;
}

Billboard computeBillboard(const RoundedCone& cone, const glm::mat4& viewProj, const Camera& camera) {
    return computeBillboard(cone, viewProj, camera.eye, camera.projection == Projection::Orthographic,
                            camera.forward());
}

}  // namespace tc
