// intersectRoundedCone against an independent double-precision ground truth: sphere tracing and
// bisection on sdRoundedCone along the ray.
#include "core/rounded_cone.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace tc {
namespace {

using glm::dvec3;

struct MarchResult {
    bool hit = false;
    double tIn = 0, tOut = 0;
    double minDistance = std::numeric_limits<double>::infinity();  // min sd seen (misses)
    double midDistance = 0;                                        // sd at the chord middle (hits)
};

// Sphere tracing from both ends of the bounding sphere's chord; sd is exact outside, so the march
// never steps into the shape and stops within `eps` of the surface.
MarchResult march(const RayD& ray, const RoundedConeD& c) {
    dvec3 m = 0.5 * (c.x0 + c.x1);
    double R = 0.5 * glm::length(c.x1 - c.x0) + std::max(c.r0, c.r1);
    double tc = glm::dot(m - ray.origin, ray.dir);
    double scale = R + std::abs(tc);
    double eps = 1e-13 * scale;
    double tA = tc - 1.5 * R, tB = tc + 1.5 * R;
    MarchResult r;
    auto sd = [&](double t) { return sdRoundedCone(ray.origin + t * ray.dir, c); };
    double t = tA;
    bool found = false;
    for (int i = 0; i < 2000000 && t <= tB; ++i) {
        double d = sd(t);
        r.minDistance = std::min(r.minDistance, d);
        if (d < eps) {
            found = true;
            break;
        }
        t += d;
    }
    if (!found) return r;
    r.hit = true;
    r.tIn = t;
    t = tB;
    for (int i = 0; i < 2000000 && t >= tA; ++i) {
        double d = sd(t);
        if (d < eps) break;
        t -= d;
    }
    r.tOut = t;
    r.midDistance = sd(0.5 * (r.tIn + r.tOut));
    return r;
}

dvec3 gradient(const RoundedConeD& c, dvec3 p, double h) {
    auto f = [&](dvec3 q) { return sdRoundedCone(q, c); };
    dvec3 g(f(p + dvec3(h, 0, 0)) - f(p - dvec3(h, 0, 0)), f(p + dvec3(0, h, 0)) - f(p - dvec3(0, h, 0)),
            f(p + dvec3(0, 0, h)) - f(p - dvec3(0, 0, h)));
    return glm::normalize(g);
}

enum class ConeKind { General, BigSmall, Cylinder, NearlyContained, Contained, ZeroLength };
enum class RayKind { Outside, Inside, AlongAxis };

struct Case {
    RoundedCone cone;
    Ray ray;
};

Case randomCase(std::mt19937& rng, ConeKind kind, RayKind rayKind) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
    auto logUniform = [&](float lo, float hi) { return lo * std::pow(hi / lo, u01(rng)); };
    auto unit = [&] {
        glm::vec3 v;
        do v = {u(rng), u(rng), u(rng)};
        while (glm::dot(v, v) > 1.0f || glm::dot(v, v) < 1e-4f);
        return glm::normalize(v);
    };
    RoundedCone c;
    c.x0 = {u(rng), u(rng), u(rng)};
    c.r0 = logUniform(0.01f, 0.4f);
    float len = logUniform(0.02f, 2.0f);
    glm::vec3 axis = unit();
    c.r1 = logUniform(0.01f, 0.4f);
    switch (kind) {
        case ConeKind::General:
            break;
        case ConeKind::BigSmall:
            c.r1 = c.r0 * logUniform(0.005f, 0.05f);
            break;
        case ConeKind::Cylinder:
            c.r1 = c.r0;
            break;
        case ConeKind::NearlyContained:
            len = std::abs(c.r0 - c.r1) * (1.0f + logUniform(1e-4f, 1e-1f));
            break;
        case ConeKind::Contained:
            len = std::abs(c.r0 - c.r1) * u01(rng);
            break;
        case ConeKind::ZeroLength:
            len = 0.0f;
            break;
    }
    c.x1 = c.x0 + len * axis;
    if (u01(rng) < 0.5f) std::swap(c.x0, c.x1), std::swap(c.r0, c.r1);
    glm::vec3 mid = 0.5f * (c.x0 + c.x1);
    float R = 0.5f * len + std::max(c.r0, c.r1);
    Ray ray;
    if (rayKind == RayKind::Outside) {
        ray.origin = mid + unit() * (R + logUniform(0.01f, 3.0f));
        glm::vec3 aim = mid + unit() * (R * 1.1f * u01(rng));
        ray.dir = glm::normalize(aim - ray.origin);
    } else if (rayKind == RayKind::Inside) {
        float s = u01(rng);
        glm::vec3 onAxis = glm::mix(c.x0, c.x1, s);
        ray.origin = onAxis + unit() * (0.5f * std::min(c.r0, c.r1) * u01(rng));
        ray.dir = unit();
    } else {
        glm::vec3 a = len > 0 ? glm::normalize(c.x1 - c.x0) : glm::vec3(0, 0, 1);
        glm::vec3 side = glm::normalize(glm::cross(a, unit()));
        ray.origin = c.x0 - a * (R + 1.0f) + side * (1.2f * std::max(c.r0, c.r1) * u01(rng));
        ray.dir = u01(rng) < 0.5f ? a : -a;
        if (u01(rng) < 0.5f)
            ray.origin = c.x1 + a * (R + 1.0f) + side * (1.2f * std::max(c.r0, c.r1) * u01(rng)), ray.dir = -a;
    }
    return {c, ray};
}

RoundedConeD toDouble(const RoundedCone& c) {
    return {dvec3(c.x0), double(c.r0), dvec3(c.x1), double(c.r1)};
}
RayD toDouble(const Ray& r) {
    return {dvec3(r.origin), glm::normalize(dvec3(r.dir))};
}

bool finite(const ConeInterval& i) {
    return std::isfinite(i.tIn) && std::isfinite(i.tOut) && std::isfinite(i.nIn.x) && std::isfinite(i.nIn.y) &&
           std::isfinite(i.nIn.z) && std::isfinite(i.nOut.x) && std::isfinite(i.nOut.y) && std::isfinite(i.nOut.z);
}

double angle(dvec3 a, dvec3 b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Tolerances. Inputs are float, so a point of the ray is known to ~6e-8 * (its distance from the
// origin plus the coordinates' magnitude); shallow incidence amplifies that error along the ray
// by 1/sin(incidence) <= ~70 for the non-grazing rays kept here (grazing: closer than 1e-4 r).
// 2e-5 of the scene scale covers that with margin; normals: 2e-3 rad (float normal of a point
// off by ~1e-6 of r).
constexpr double kTolT = 2e-5;
constexpr double kTolNormalRad = 2e-3;
constexpr double kGrazing = 1e-4;

void checkAgainstMarch(ConeKind kind, RayKind rayKind, unsigned seed) {
    std::mt19937 rng(seed);
    int checked = 0, hits = 0, grazing = 0;
    double worstT = 0, worstN = 0;
    for (int i = 0; i < 3000; ++i) {
        Case cs = randomCase(rng, kind, rayKind);
        ConeInterval got = intersectRoundedCone(cs.ray, cs.cone);
        ASSERT_TRUE(finite(got)) << "case " << i;
        RoundedConeD c = toDouble(cs.cone);
        RayD ray = toDouble(cs.ray);
        MarchResult ref = march(ray, c);
        double rmin = std::min(c.r0, c.r1);
        bool isGrazing = ref.hit ? ref.midDistance > -kGrazing * rmin : ref.minDistance < kGrazing * rmin;
        if (isGrazing) {
            ++grazing;
            continue;
        }
        ++checked;
        ASSERT_EQ(got.hit, ref.hit) << "case " << i << " kind " << int(kind);
        if (!ref.hit) continue;
        ++hits;
        double scale = glm::length(ray.origin - 0.5 * (c.x0 + c.x1)) + glm::length(c.x1 - c.x0) + std::max(c.r0, c.r1);
        double eT = std::max(std::abs(got.tIn - ref.tIn), std::abs(got.tOut - ref.tOut)) / scale;
        worstT = std::max(worstT, eT);
        EXPECT_LT(eT, kTolT) << "case " << i << " tIn " << got.tIn << " vs " << ref.tIn << ", tOut " << got.tOut
                             << " vs " << ref.tOut;
        double h = 1e-7 * scale;
        double eN = std::max(angle(dvec3(got.nIn), gradient(c, ray.origin + ref.tIn * ray.dir, h)),
                             angle(dvec3(got.nOut), gradient(c, ray.origin + ref.tOut * ray.dir, h)));
        worstN = std::max(worstN, eN);
        EXPECT_LT(eN, kTolNormalRad) << "case " << i;
        EXPECT_NEAR(glm::length(got.nIn), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::length(got.nOut), 1.0f, 1e-5f);
    }
    // Enough of the cases must be real checks, not grazing or trivial misses.
    EXPECT_GT(checked, 2500);
    EXPECT_GT(hits, 300);
    std::printf("kind %d ray %d: checked %d hits %d grazing %d worst |dt|/scale %.3g worst normal %.3g rad\n",
                int(kind), int(rayKind), checked, hits, grazing, worstT, worstN);
}

TEST(RoundedCone, intersection_matches_double_march_general_cones) {
    checkAgainstMarch(ConeKind::General, RayKind::Outside, 1);
}
TEST(RoundedCone, intersection_matches_double_march_when_r0_much_larger_than_r1) {
    checkAgainstMarch(ConeKind::BigSmall, RayKind::Outside, 2);
}
TEST(RoundedCone, intersection_matches_double_march_for_cylinders) {
    checkAgainstMarch(ConeKind::Cylinder, RayKind::Outside, 3);
}
TEST(RoundedCone, intersection_matches_double_march_when_spheres_nearly_contain_each_other) {
    checkAgainstMarch(ConeKind::NearlyContained, RayKind::Outside, 4);
}
TEST(RoundedCone, intersection_is_the_bigger_sphere_when_one_contains_the_other) {
    checkAgainstMarch(ConeKind::Contained, RayKind::Outside, 5);
}
TEST(RoundedCone, intersection_is_a_sphere_for_zero_length_segments) {
    checkAgainstMarch(ConeKind::ZeroLength, RayKind::Outside, 6);
}
TEST(RoundedCone, intersection_matches_double_march_for_rays_starting_inside) {
    checkAgainstMarch(ConeKind::General, RayKind::Inside, 7);
    checkAgainstMarch(ConeKind::BigSmall, RayKind::Inside, 8);
}
TEST(RoundedCone, intersection_matches_double_march_for_rays_parallel_to_the_axis) {
    checkAgainstMarch(ConeKind::General, RayKind::AlongAxis, 9);
    checkAgainstMarch(ConeKind::Cylinder, RayKind::AlongAxis, 10);
    checkAgainstMarch(ConeKind::BigSmall, RayKind::AlongAxis, 11);
}

TEST(RoundedCone, rays_from_inside_have_negative_entry_and_positive_exit) {
    RoundedCone c{{0, 0, 0}, 0.2f, {1, 0, 0}, 0.1f};
    ConeInterval i = intersectRoundedCone({{0.5f, 0, 0}, {0, 1, 0}}, c);
    ASSERT_TRUE(i.hit);
    EXPECT_LT(i.tIn, 0.0f);
    EXPECT_GT(i.tOut, 0.0f);
    EXPECT_NEAR(i.tOut, -i.tIn, 1e-6f);
    EXPECT_GT(i.nOut.y, 0.9f);
}

TEST(RoundedCone, nearest_positive_hit_is_the_entry_ahead_else_the_exit_else_nothing) {
    RoundedCone c{{0, 0, 0}, 0.2f, {1, 0, 0}, 0.1f};
    // From outside, in front: the entry.
    auto ahead = nearestPositiveHit(intersectRoundedCone({{0.5f, -1, 0}, {0, 1, 0}}, c));
    ASSERT_TRUE(ahead.has_value());
    EXPECT_GT(ahead->t, 0.0f);
    EXPECT_LT(ahead->normal.y, -0.9f);
    // From inside: the exit, with the outward normal of the far side.
    ConeInterval inside = intersectRoundedCone({{0.5f, 0, 0}, {0, 1, 0}}, c);
    auto exit = nearestPositiveHit(inside);
    ASSERT_TRUE(exit.has_value());
    EXPECT_EQ(exit->t, inside.tOut);
    EXPECT_GT(exit->normal.y, 0.9f);
    // The cone wholly behind the origin, and a miss: nothing.
    EXPECT_FALSE(nearestPositiveHit(intersectRoundedCone({{0.5f, 1, 0}, {0, 1, 0}}, c)).has_value());
    EXPECT_FALSE(nearestPositiveHit(intersectRoundedCone({{0.5f, -1, 0}, {1, 0, 0}}, c)).has_value());
}

// firstSurfaceHit normalizes only the normal it returns; the CPU reference and the Embree path's
// re-intersection rely on it giving nearestPositiveHit(intersectRoundedCone) bit for bit.
TEST(RoundedCone, first_surface_hit_is_nearest_positive_hit_bit_for_bit) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), r(0.01f, 0.3f);
    int hits = 0, insides = 0;
    for (int i = 0; i < 20000; ++i) {
        RoundedCone c{{u(rng), u(rng), u(rng)}, r(rng), {u(rng), u(rng), u(rng)}, r(rng)};
        if (i % 7 == 0) c.x1 = c.x0;  // zero-length segments
        // Origins spread around the cone (some inside it), directions towards its middle jittered.
        const glm::vec3 mid = 0.5f * (c.x0 + c.x1);
        const glm::vec3 origin = mid + (i % 5 == 0 ? 0.1f : 2.0f) * glm::vec3(u(rng), u(rng), u(rng));
        const glm::vec3 dir = glm::normalize(mid - origin + 0.3f * glm::vec3(u(rng), u(rng), u(rng)));
        const Ray ray{origin, dir};
        const ConeInterval iv = intersectRoundedCone(ray, c);
        const auto expected = nearestPositiveHit(iv);
        const auto got = firstSurfaceHit(ray, c);
        ASSERT_EQ(got.has_value(), expected.has_value()) << i;
        if (!got) continue;
        ++hits;
        if (iv.tIn <= 0.0f) ++insides;
        EXPECT_EQ(got->t, expected->t) << i;
        EXPECT_EQ(got->normal.x, expected->normal.x) << i;
        EXPECT_EQ(got->normal.y, expected->normal.y) << i;
        EXPECT_EQ(got->normal.z, expected->normal.z) << i;
    }
    EXPECT_GT(hits, 5000);    // the rays do meet their cones
    EXPECT_GT(insides, 100);  // and the exit branch is taken
}

TEST(RoundedCone, grazing_and_degenerate_rays_never_produce_nan) {
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    // Rays exactly tangent to spheres and cylinders, exactly along the axis through the centre,
    // zero-length segments and equal spheres.
    std::vector<RoundedCone> cones = {{{0, 0, 0}, 0.1f, {1, 0, 0}, 0.1f},
                                      {{0, 0, 0}, 0.1f, {0, 0, 0}, 0.1f},
                                      {{0, 0, 0}, 0.3f, {0.1f, 0, 0}, 0.1f},
                                      {{0, 0, 0}, 0.1f, {0.2f, 0, 0}, 0.1f}};
    for (const RoundedCone& c : cones) {
        for (Ray r : {Ray{{-2, 0, 0}, {1, 0, 0}}, Ray{{-2, 0.1f, 0}, {1, 0, 0}}, Ray{{0, 0.1f, -3}, {0, 0, 1}},
                      Ray{{0.5f, 0.1f, -3}, {0, 0, 1}}, Ray{{3, 0, 0}, {-1, 0, 0}}, Ray{{0, 0, 0}, {1, 0, 0}}}) {
            ConeInterval i = intersectRoundedCone(r, c);
            EXPECT_TRUE(finite(i));
            if (i.hit) {
                EXPECT_LE(i.tIn, i.tOut);
            }
        }
    }
    for (int k = 0; k < 20000; ++k) {
        RoundedCone c{{u(rng), u(rng), u(rng)}, 0.05f + 0.1f * std::abs(u(rng)), {u(rng), u(rng), u(rng)}, 0.05f};
        glm::vec3 d = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + 1e-3f);
        glm::vec3 n = glm::normalize(glm::cross(d, glm::vec3(0.3f, 0.7f, 0.1f)));
        // Rays through a point at distance exactly r from a sphere centre, perpendicular: tangent.
        Ray r{c.x0 + n * c.r0 - 3.0f * d, d};
        ConeInterval i = intersectRoundedCone(r, c);
        EXPECT_TRUE(finite(i));
        if (i.hit) {
            EXPECT_LE(i.tIn, i.tOut);
        }
    }
}

// Thin tubes far away: the float solve must keep depth precision (the frame shift at work).
TEST(RoundedCone, thin_far_tube_depth_matches_double_to_1e_5_relative) {
    RoundedCone c{{-0.3f, 0.013f, -2.0f}, 1e-3f, {0.4f, -0.007f, -2.05f}, 0.7e-3f};
    RoundedConeD cd = toDouble(c);
    glm::vec3 eye(0.0f, 0.0f, 0.0f);
    double worst = 0;
    int hits = 0;
    for (int i = 0; i <= 4000; ++i) {
        float s = float(i) / 4000.0f;
        // Rays across the tube at several places along it.
        glm::vec3 onAxis = glm::mix(c.x0, c.x1, std::fmod(7.31f * s, 1.0f));
        glm::vec3 across(0.0f, 1.0f, 0.0f);
        glm::vec3 target = onAxis + across * ((2.0f * s - 1.0f) * 1.2e-3f);
        Ray ray{eye, glm::normalize(target - eye)};
        ConeInterval f = intersectRoundedCone(ray, c);
        ConeIntervalD d = intersectRoundedCone(toDouble(ray), cd);
        ASSERT_TRUE(finite(f));
        if (!d.hit) continue;
        // Leave out the outermost 1 % of the radius: there dt/d(offset) diverges and the
        // question is the solve, not the silhouette.
        MarchResult m = march(toDouble(ray), cd);
        if (m.midDistance > -0.02 * 0.7e-3) continue;
        ASSERT_TRUE(f.hit) << i;
        ++hits;
        worst = std::max(worst, std::abs(double(f.tIn) - d.tIn) / d.tIn);
        EXPECT_LT(std::abs(double(f.tIn) - d.tIn) / d.tIn, 1e-5) << i;
        EXPECT_LT(std::abs(double(f.tIn) - m.tIn) / m.tIn, 1e-5) << i;
        EXPECT_LT(std::abs(double(f.tOut) - d.tOut) / d.tOut, 1e-5) << i;
    }
    EXPECT_GT(hits, 1000);
    std::printf("thin far tube: %d hits, worst relative depth error %.3g\n", hits, worst);
}

TEST(RoundedCone, signed_distance_is_zero_on_the_surface_and_negative_on_the_axis) {
    RoundedCone c{{0, 0, 0}, 0.3f, {1, 0, 0}, 0.1f};
    EXPECT_NEAR(sdRoundedCone({-0.3f, 0, 0}, c), 0.0f, 1e-6f);
    EXPECT_NEAR(sdRoundedCone({1.1f, 0, 0}, c), 0.0f, 1e-6f);
    EXPECT_NEAR(sdRoundedCone({-1.0f, 0, 0}, c), 0.7f, 1e-6f);
    EXPECT_LT(sdRoundedCone({0.5f, 0, 0}, c), 0.0f);
    // Lateral: the tangent line of the profile at s = rr/L = 0.2.
    float s = 0.2f, cc = std::sqrt(1 - s * s);
    glm::vec3 onSurface = glm::vec3(0.3f * s, 0.3f * cc, 0) + 0.5f * glm::vec3(cc, -s, 0);
    EXPECT_NEAR(sdRoundedCone(onSurface, c), 0.0f, 1e-6f);
    EXPECT_NEAR(sdRoundedCone(onSurface + 0.25f * glm::vec3(s, cc, 0), c), 0.25f, 1e-6f);
}

}  // namespace
}  // namespace tc
