#include "core/billboard.h"

#include <cmath>
#include <optional>

namespace tc {
namespace {

constexpr std::array<glm::vec2, 4> kFullscreen = {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(-1, 1),
                                                  glm::vec2(1, 1)};
// Zero area and off screen: rasterises nothing.
constexpr std::array<glm::vec2, 4> kCulled = {glm::vec2(-2, -2), glm::vec2(-2, -2), glm::vec2(-2, -2),
                                              glm::vec2(-2, -2)};

using Quad = std::array<glm::vec2, 4>;

// A unit vector perpendicular to v (unit).
glm::vec3 anyPerpendicular(glm::vec3 v) {
    glm::vec3 a = std::abs(v.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    return glm::normalize(glm::cross(v, a));
}

// The eye's tangent-cone radius around sphere (x, r) in the plane through x perpendicular to
// eye - x: |d| r / sqrt(|d|^2 - r^2) (Eq. 2-3); (D - r)(D + r) avoids cancellation. r itself for
// an orthographic view. Empty when the eye is (within rounding) on the sphere.
std::optional<float> tangentRadius(glm::vec3 x, float r, glm::vec3 eye, bool orthographic) {
    if (orthographic) return r;
    float D = glm::length(eye - x);
    float k = (D - r) * (D + r);
    if (!(k > 1e-8f * D * D)) return std::nullopt;
    return D * r / std::sqrt(k);
}

// Projects p; empty when p is at or behind the eye plane relative to `reference` (clip w).
std::optional<glm::vec2> project(const glm::mat4& viewProj, glm::vec3 p, float referenceW) {
    glm::vec4 c = viewProj * glm::vec4(p, 1.0f);
    if (!(c.w > 1e-6f * referenceW)) return std::nullopt;
    return glm::vec2(c) / c.w;
}

std::optional<Quad> rectangleQuad(const RoundedCone& c, const glm::mat4& viewProj, glm::vec3 eye, bool orthographic,
                                  glm::vec3 forward) {
    glm::vec3 ba = c.x1 - c.x0;
    glm::vec3 x[2] = {c.x0, c.x1};
    float r[2] = {c.r0, c.r1};
    glm::vec2 pts[8];
    glm::vec2 centre[2];
    for (int i = 0; i < 2; ++i) {
        glm::vec3 di = eye - x[i];
        glm::vec3 v = orthographic ? -forward : di / glm::length(di);
        std::optional<float> rp = tangentRadius(x[i], r[i], eye, orthographic);
        if (!rp) return std::nullopt;
        // b, then a = b x v: orthonormal and perpendicular to v even when the view runs nearly
        // along the axis (ba - v (ba . v) would cancel there and leave a skewed, shrunken square).
        glm::vec3 b = glm::cross(v, ba);
        float lb = glm::length(b);
        b = lb > 1e-6f * glm::length(ba) && lb > 0.0f ? b / lb : anyPerpendicular(v);
        glm::vec3 a = glm::cross(b, v);
        glm::vec4 cc = viewProj * glm::vec4(x[i], 1.0f);
        centre[i] = glm::vec2(cc) / cc.w;
        for (int k = 0; k < 4; ++k) {
            float sa = (k & 1) ? 1.0f : -1.0f, sb = (k & 2) ? 1.0f : -1.0f;
            // A square corner at or behind the eye plane (a sphere close to it): no finite quad.
            std::optional<glm::vec2> p = project(viewProj, x[i] + (sa * *rp) * a + (sb * *rp) * b, cc.w);
            if (!p) return std::nullopt;
            pts[4 * i + k] = *p;
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
    return Quad{loE * e + loF * f, hiE * e + loF * f, loE * e + hiF * f, hiE * e + hiF * f};
}

// Groß & Gumhold 2020, Eq. 1-10 (see billboard.h). `degenerate` is set, and nothing returned,
// when the view runs (nearly) along the axis: u is undefined there.
std::optional<Quad> gross2020Quad(const RoundedCone& cone, const glm::mat4& viewProj, glm::vec3 eye, bool orthographic,
                                  glm::vec3 forward, bool& degenerate) {
    degenerate = false;
    // Sect. 5.1: the construction takes r0 <= r1; otherwise swap the ends.
    RoundedCone c = cone;
    if (c.r0 > c.r1) c = {cone.x1, cone.r1, cone.x0, cone.r0};
    glm::vec3 d = c.x1 - c.x0;
    glm::vec3 d0 = orthographic ? -forward : eye - c.x0;
    glm::vec3 d1 = orthographic ? -forward : eye - c.x1;
    float D0 = orthographic ? 1.0f : glm::length(d0), D1 = orthographic ? 1.0f : glm::length(d1);
    glm::vec3 uu = glm::cross(d, d0);  // Eq. 1; d x d1 is the same vector
    float lu = glm::length(uu);
    if (!(lu > 1e-6f * glm::length(d) * D0)) {
        degenerate = true;
        return std::nullopt;
    }
    // The cross product of nearly parallel vectors is off in direction by ~1e-7 / sin(angle); the
    // error out of the plane perpendicular to d0 is removed (u must be perpendicular to d0 and
    // d1 for the tangent planes), what is left turns the plane through the eye and the axis about
    // d0 and moves x1 out of it by only ~1e-7 |d|.
    glm::vec3 n0 = glm::normalize(d0);
    glm::vec3 u = glm::normalize(uu / lu - n0 * glm::dot(uu / lu, n0));
    glm::vec3 v0 = glm::normalize(glm::cross(u, d0)), v1 = glm::normalize(glm::cross(u, d1));
    std::optional<float> rp0 = tangentRadius(c.x0, c.r0, eye, orthographic);
    std::optional<float> rp1 = tangentRadius(c.x1, c.r1, eye, orthographic);
    if (!rp0 || !rp1) return std::nullopt;
    // Eq. 4: silhouette points in the plane through the eye and the axis.
    glm::vec3 p[4] = {c.x0 + *rp0 * v0, c.x0 - *rp0 * v0, c.x1 + *rp1 * v1, c.x1 - *rp1 * v1};
    // Eq. 2 and 5: s_i = r'_i / |d_i|, the tangent of sphere i's angular radius; the larger one at
    // both ends keeps the side edges outside the larger-looking sphere.
    float sm = glm::max(*rp0 / D0, *rp1 / D1);
    float rpp0 = D0 * sm, rpp1 = D1 * sm;
    // Eq. 6-9: w lies in the plane through the eye and the axis, perpendicular to the view; the
    // smaller angle to w is the farther point on the p0 / p2 side. Orthographic: positions along w.
    glm::vec3 w = glm::normalize(glm::cross(u, forward));
    float alpha[4];
    for (int i = 0; i < 4; ++i)
        alpha[i] = orthographic ? glm::dot(p[i] - eye, w) : glm::dot(glm::normalize(p[i] - eye), w);
    glm::vec3 ps = alpha[0] <= alpha[2] ? p[0] : p[2];
    float rs = alpha[0] <= alpha[2] ? rpp0 : rpp1;
    glm::vec3 pe = alpha[1] <= alpha[3] ? p[3] : p[1];
    float re = alpha[1] <= alpha[3] ? rpp1 : rpp0;
    // Eq. 10.
    glm::vec3 corners[4] = {ps - rs * u, ps + rs * u, pe - re * u, pe + re * u};
    float referenceW = glm::max((viewProj * glm::vec4(c.x0, 1.0f)).w, (viewProj * glm::vec4(c.x1, 1.0f)).w);
    Quad q;
    for (int k = 0; k < 4; ++k) {
        std::optional<glm::vec2> pk = project(viewProj, corners[k], referenceW);
        if (!pk) return std::nullopt;
        q[k] = *pk;
    }
    return q;
}

float cross2(glm::vec2 a, glm::vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Moves every edge of q (strip order; polygon order 0,1,3,2) outward by `pad`: each corner by
// the miter of its two edges' normals.
Quad padQuad(const Quad& q, float pad) {
    const int order[4] = {0, 1, 3, 2};
    glm::vec2 poly[4];
    for (int i = 0; i < 4; ++i) poly[i] = q[order[i]];
    float area = 0;
    for (int i = 0; i < 4; ++i) area += cross2(poly[i], poly[(i + 1) % 4]);
    float orient = area < 0 ? -1.0f : 1.0f;
    glm::vec2 normal[4];
    for (int i = 0; i < 4; ++i) {
        glm::vec2 e = poly[(i + 1) % 4] - poly[i];
        float le = glm::length(e);
        normal[i] = le > 0.0f ? orient * glm::vec2(e.y, -e.x) / le : glm::vec2(0.0f);
    }
    Quad out;
    for (int i = 0; i < 4; ++i) {
        glm::vec2 na = normal[(i + 3) % 4], nb = normal[i];
        if (na == glm::vec2(0.0f)) na = nb;
        if (nb == glm::vec2(0.0f)) nb = na;
        // Corners of a quad from Eq. 10 are near right angles; the cap keeps a sliver's miter finite.
        glm::vec2 delta = pad * (na + nb) / glm::max(1.0f + glm::dot(na, nb), 0.1f);
        out[order[i]] = poly[i] + delta;
    }
    return out;
}

}  // namespace

Billboard computeBillboard(const RoundedCone& c, const glm::mat4& viewProj, const glm::vec3& eye, bool orthographic,
                           const glm::vec3& forward, BillboardShape shape) {
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

    bool degenerate = true;
    std::optional<Quad> q;
    if (shape == BillboardShape::Gross2020) q = gross2020Quad(c, viewProj, eye, orthographic, forward, degenerate);
    if (degenerate) q = rectangleQuad(c, viewProj, eye, orthographic, forward);
    if (!q) return bb;

    glm::vec2 lo(3.0e38f), hi(-3.0e38f);
    for (const glm::vec2& p : *q) lo = glm::min(lo, p), hi = glm::max(hi, p);
    glm::vec2 size = hi - lo;
    if (!(size.x < 1e30f && size.y < 1e30f)) return bb;  // overflow or NaN: stay conservative
    bb.ndc = padQuad(*q, 1e-5f * glm::max(size.x, size.y) + 1e-6f);
    bb.fullscreen = false;
    return bb;
}

Billboard computeBillboard(const RoundedCone& cone, const glm::mat4& viewProj, const Camera& camera,
                           BillboardShape shape) {
    return computeBillboard(cone, viewProj, camera.eye, camera.projection == Projection::Orthographic, camera.forward(),
                            shape);
}

}  // namespace tc
