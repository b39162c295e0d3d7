#include "core/rounded_cone.h"

#include <cmath>
#include <limits>

namespace tc {
namespace {

// One implementation for float and double (the double one exists to measure the float one).
// nIn / nOut are the candidates' outward normals NOT yet normalized: the callers normalize only
// the ones they return (of up to six candidates, as shaders/rounded_cone.glsl), and normalizing
// the same vector later gives the same bits as normalizing it at once.
template <typename T>
struct IntervalT {
    bool hit = false;
    T tIn = 0, tOut = 0;
    glm::vec<3, T> nIn{0}, nOut{0};
};

template <typename T>
IntervalT<T> intersectImpl(glm::vec<3, T> o, glm::vec<3, T> dir, glm::vec<3, T> x0, T r0, glm::vec<3, T> x1, T r1) {
    using V = glm::vec<3, T>;
    // Parameters beyond this are treated as "no root" (a linear equation's root at infinity).
    constexpr T kHuge = T(1e18);
    constexpr T kFar = T(1e30);

    V ba = x1 - x0;
    T L = glm::length(ba);
    T rr = r0 - r1;
    V u = L > T(0) ? ba / L : V(0);
    T m2 = glm::dot(dir, u);
    V uxd = glm::cross(u, dir);
    T sin2 = glm::dot(uxd, uxd);  // 1 - m2^2, exact for rays nearly parallel to the axis

    // Solve in a frame centred on xc, the axis point closest to the ray, with the origin moved to
    // the ray point closest to xc: thin tubes (r ~ 1e-3) seen from far away (distance ~ 2) would
    // otherwise lose most float digits in |o - x|^2 - r^2 (and, along long segments, in the
    // lateral quadric's y^2 terms).
    V w0 = o - x0;
    T ac = T(0);
    if (sin2 > T(1e-6)) ac = glm::clamp((glm::dot(w0, u) - m2 * glm::dot(w0, dir)) / sin2, T(0), L);
    V xc = x0 + ac * u;
    T t0 = glm::dot(xc - o, dir);
    V oa = (o - xc) + t0 * dir;

    T tIn = kFar, tOut = -kFar;
    V nIn(0), nOut(0);
    bool hit = false;

    // Spheres: discriminant from the perpendicular offset (no cancellation near the silhouette).
    auto sphere = [&](V oc, T r) {
        T b = glm::dot(oc, dir);
        V perp = oc - b * dir;
        T h = r * r - glm::dot(perp, perp);
        if (h < T(0)) return;
        T sq = std::sqrt(h);
        T ta = -b - sq, tb = -b + sq;
        hit = true;
        if (ta < tIn) {
            tIn = ta;
            nIn = perp - sq * dir;
        }
        if (tb > tOut) {
            tOut = tb;
            nOut = perp + sq * dir;
        }
    };
    sphere(oa + ac * u, r0);
    sphere(oa - (L - ac) * u, r1);

    // Lateral surface of the common tangent cone, axis normalised (s = rr/L, c2 = 1 - s^2) and
    // written around xc, where the cone's "radius" is rc = r0 - s ac:
    //   c2 |q|^2 - y^2 + 2 rc s y - rc^2 = 0,  q = oa + t dir,  y = dot(q, u),
    // valid where (y - rc s) + c2 ac, the axial coordinate measured from sphere 0's tangent circle,
    // lies in [0, L c2]. Without a lateral surface (L <= |rr|: one sphere contains the other, or
    // a zero-length segment) the union of the spheres already is the shape.
    if (L > std::abs(rr)) {
        T s = rr / L;
        T c2 = (T(1) - s) * (T(1) + s);
        T rc = r0 - s * ac;
        T m1 = glm::dot(oa, u), m3 = glm::dot(oa, dir);
        T k2 = sin2 - s * s;
        T w = m1 - rc * s;
        T k1 = c2 * m3 - m2 * w;
        T k0 = c2 * (glm::dot(oa, oa) - rc * rc) - w * w;
        T h = k1 * k1 - k0 * k2;
        if (h >= T(0)) {
            T sq = std::sqrt(h);
            // Stable roots q/k2 and k0/q. The root where the quadric's derivative k1 + k2 t is
            // -sqrt(h) enters the cone (the gradient points outward on the real nappe), whatever
            // the sign of k2.
            T q = -(k1 + (k1 >= T(0) ? sq : -sq));
            bool validA = std::abs(q) < kHuge * std::abs(k2);
            bool validB = std::abs(k0) < kHuge * std::abs(q);
            T tA = validA ? q / k2 : T(0);
            T tB = validB ? k0 / q : T(0);
            bool aIsEntry = k1 >= T(0);
            auto lateral = [&](T t, bool entry) {
                T yc = w + t * m2;  // y - rc s: the normal's axial part
                T ya = yc + c2 * ac;
                if (!(ya >= T(0) && ya <= L * c2)) return;
                V n = c2 * (oa + t * dir) - u * yc;
                hit = true;
                if (entry && t < tIn) {
                    tIn = t;
                    nIn = n;
                }
                if (!entry && t > tOut) {
                    tOut = t;
                    nOut = n;
                }
            };
            if (validA) lateral(tA, aIsEntry);
            if (validB) lateral(tB, !aIsEntry);
        }
    }

    IntervalT<T> result;
    if (!hit) return result;
    // A ray grazing a seam between pieces can lose one end to rounding: close the interval.
    if (tOut < tIn) {
        if (tOut == -kFar) {
            tOut = tIn;
            nOut = nIn;
        } else if (tIn == kFar) {
            tIn = tOut;
            nIn = nOut;
        } else {
            T m = T(0.5) * (tIn + tOut);
            tIn = tOut = m;
        }
    }
    result.hit = true;
    result.tIn = t0 + tIn;
    result.tOut = t0 + tOut;
    result.nIn = nIn;
    result.nOut = nOut;
    return result;
}

template <typename T>
T sdImpl(glm::vec<3, T> p, glm::vec<3, T> x0, T r0, glm::vec<3, T> x1, T r1) {
    using V = glm::vec<3, T>;
    V ba = x1 - x0;
    T L = glm::length(ba);
    T rr = r0 - r1;
    if (!(L > std::abs(rr))) return r0 >= r1 ? glm::length(p - x0) - r0 : glm::length(p - x1) - r1;
    // 2D problem in (axial y, radial rho): the hull of discs (0, r0) and (L, r1). The lateral
    // line has outward normal (s, c); the lines through the centres perpendicular to it split
    // the half plane into the regions of sphere 0, the lateral line and sphere 1.
    V u = ba / L;
    T s = rr / L;
    T c = std::sqrt((T(1) - s) * (T(1) + s));
    V pa = p - x0;
    T y = glm::dot(pa, u);
    T rho = glm::length(pa - y * u);
    T k = y * c - rho * s;
    if (k < T(0)) return glm::length(pa) - r0;
    if (k > L * c) return glm::length(p - x1) - r1;
    return y * s + rho * c - r0;
}

}  // namespace

std::optional<SurfaceHit> nearestPositiveHit(const ConeInterval& iv) {
    if (!iv.hit) return std::nullopt;
    if (iv.tIn > 0.0f) return SurfaceHit{iv.tIn, iv.nIn};
    if (iv.tOut > 0.0f) return SurfaceHit{iv.tOut, iv.nOut};
    return std::nullopt;
}

ConeInterval intersectRoundedCone(const Ray& ray, const RoundedCone& c) {
    IntervalT<float> i = intersectImpl<float>(ray.origin, ray.dir, c.x0, c.r0, c.x1, c.r1);
    if (!i.hit) return {false, 0.0f, 0.0f, glm::vec3(0.0f), glm::vec3(0.0f)};
    return {true, i.tIn, i.tOut, glm::normalize(i.nIn), glm::normalize(i.nOut)};
}

std::optional<SurfaceHit> firstSurfaceHit(const Ray& ray, const RoundedCone& c) {
    // nearestPositiveHit(intersectRoundedCone(ray, c)) with one normalization instead of two.
    IntervalT<float> i = intersectImpl<float>(ray.origin, ray.dir, c.x0, c.r0, c.x1, c.r1);
    if (!i.hit) return std::nullopt;
    if (i.tIn > 0.0f) return SurfaceHit{i.tIn, glm::normalize(i.nIn)};
    if (i.tOut > 0.0f) return SurfaceHit{i.tOut, glm::normalize(i.nOut)};
    return std::nullopt;
}

ConeIntervalD intersectRoundedCone(const RayD& ray, const RoundedConeD& c) {
    IntervalT<double> i = intersectImpl<double>(ray.origin, ray.dir, c.x0, c.r0, c.x1, c.r1);
    if (!i.hit) return {false, 0.0, 0.0, glm::dvec3(0.0), glm::dvec3(0.0)};
    return {true, i.tIn, i.tOut, glm::normalize(i.nIn), glm::normalize(i.nOut)};
}

float sdRoundedCone(glm::vec3 p, const RoundedCone& c) {
    return sdImpl<float>(p, c.x0, c.r0, c.x1, c.r1);
}

double sdRoundedCone(const glm::dvec3& p, const RoundedConeD& c) {
    return sdImpl<double>(p, c.x0, c.r0, c.x1, c.r1);
}

}  // namespace tc
