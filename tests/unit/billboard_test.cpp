// Billboards must contain every projected surface point of their rounded cone, be tight, and
// degrade to a valid (full-screen or containing) quad without NaN in degenerate views.
#include "core/billboard.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace tc {
namespace {

constexpr float kAspect = 1.5f;

glm::mat4 viewProjOf(const Camera& cam) {
    return projectionMatrix(cam, kAspect, 0.01f, 100.0f) * cam.worldToCamera();
}

float cross2(glm::vec2 a, glm::vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Strip order 0,1,2,3 is polygon order 0,1,3,2.
std::array<glm::vec2, 4> polygon(const Billboard& b) {
    return {b.ndc[0], b.ndc[1], b.ndc[3], b.ndc[2]};
}

float polygonArea(const std::vector<glm::vec2>& p) {
    float a = 0;
    for (std::size_t i = 0; i < p.size(); ++i) a += cross2(p[i], p[(i + 1) % p.size()]);
    return 0.5f * std::abs(a);
}

bool insideQuad(const Billboard& b, glm::vec2 p, float eps) {
    auto q = polygon(b);
    float sign = 0;
    for (int i = 0; i < 4; ++i) {
        glm::vec2 e = q[(i + 1) % 4] - q[i];
        float len = glm::length(e);
        if (len == 0.0f) continue;
        float c = cross2(e, p - q[i]) / len;  // signed distance to the edge line
        if (sign == 0 && std::abs(c) > eps) sign = c > 0 ? 1.0f : -1.0f;
        if (sign != 0 && c * sign < -eps) return false;
    }
    return true;
}

std::vector<glm::vec2> convexHull(std::vector<glm::vec2> p) {
    std::sort(p.begin(), p.end(), [](glm::vec2 a, glm::vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    std::vector<glm::vec2> h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross2(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
        while (k >= t && cross2(h[k - 1] - h[k - 2], p[i - 1] - h[k - 2]) <= 0) --k;
        h[k++] = p[i - 1];
    }
    h.resize(k - 1);
    return h;
}

// ~2000 points on the cone's surface: both spheres and the lateral band between the tangent circles.
std::vector<glm::vec3> surfaceSamples(const RoundedCone& c, std::mt19937& rng) {
    std::normal_distribution<float> n01;
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    auto unit = [&] { return glm::normalize(glm::vec3(n01(rng), n01(rng), n01(rng))); };
    std::vector<glm::vec3> pts;
    for (int i = 0; i < 700; ++i) pts.push_back(c.x0 + c.r0 * unit());
    for (int i = 0; i < 700; ++i) pts.push_back(c.x1 + c.r1 * unit());
    glm::vec3 ba = c.x1 - c.x0;
    float L = glm::length(ba);
    if (L > std::abs(c.r0 - c.r1)) {
        glm::vec3 u = ba / L;
        float s = (c.r0 - c.r1) / L, cc = std::sqrt(1 - s * s);
        glm::vec3 e1 = glm::normalize(glm::cross(u, std::abs(u.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
        glm::vec3 e2 = glm::cross(u, e1);
        for (int i = 0; i < 700; ++i) {
            float phi = 6.2831853f * u01(rng), lam = u01(rng);
            glm::vec3 n = s * u + cc * (std::cos(phi) * e1 + std::sin(phi) * e2);
            pts.push_back(glm::mix(c.x0 + c.r0 * n, c.x1 + c.r1 * n, lam));
        }
    }
    return pts;
}

bool finite(const Billboard& b) {
    for (glm::vec2 p : b.ndc)
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
    return true;
}

struct Stats {
    int quads = 0, fullscreen = 0, culled = 0;
    double ratioSum = 0, ratioMax = 0;
};

// Every sample in front of the eye projects into the quad (full-screen quads contain the screen).
void checkContainment(const RoundedCone& c, const Camera& cam, std::mt19937& rng, Stats& st, bool expectQuad) {
    glm::mat4 vp = viewProjOf(cam);
    Billboard b = computeBillboard(c, vp, cam);
    ASSERT_TRUE(finite(b));
    std::vector<glm::vec3> samples = surfaceSamples(c, rng);
    glm::vec3 f = cam.forward();
    if (b.culled) {
        ++st.culled;
        for (glm::vec3 p : samples) ASSERT_LE(glm::dot(p - cam.eye, f), 1e-5f);
        return;
    }
    if (b.fullscreen) {
        ++st.fullscreen;
        EXPECT_FALSE(expectQuad) << "unexpected full-screen quad";
        return;
    }
    bool ortho = cam.projection == Projection::Orthographic;
    std::vector<glm::vec2> projected;
    glm::vec2 lo(1e30f), hi(-1e30f);
    for (glm::vec2 q : b.ndc) lo = glm::min(lo, q), hi = glm::max(hi, q);
    float eps = 1e-5f * glm::length(hi - lo) + 1e-6f;
    for (glm::vec3 p : samples) {
        if (!ortho) {
            ASSERT_GT(glm::dot(p - cam.eye, f), 0.0f) << "a non-full-screen quad for a cone crossing the eye plane";
        }
        glm::vec4 clip = vp * glm::vec4(p, 1.0f);
        glm::vec2 ndc = glm::vec2(clip) / clip.w;
        projected.push_back(ndc);
        ASSERT_TRUE(insideQuad(b, ndc, eps)) << "sample " << ndc.x << "," << ndc.y << " outside quad (" << b.ndc[0].x
                                             << "," << b.ndc[0].y << ") (" << b.ndc[3].x << "," << b.ndc[3].y << ")";
    }
    ++st.quads;
    auto corners = polygon(b);
    std::vector<glm::vec2> quad(corners.begin(), corners.end());
    double ratio = polygonArea(quad) / polygonArea(convexHull(projected));
    st.ratioSum += ratio;
    st.ratioMax = std::max(st.ratioMax, ratio);
}

Camera randomCamera(std::mt19937& rng, bool ortho) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
    std::normal_distribution<float> n01;
    Camera cam;
    glm::vec3 dir = glm::normalize(glm::vec3(n01(rng), n01(rng), n01(rng)));
    cam.target = {0.3f * u(rng), 0.3f * u(rng), 0.3f * u(rng)};
    cam.eye = cam.target + dir * (1.5f + 4.0f * u01(rng));
    cam.up = glm::normalize(glm::vec3(n01(rng), n01(rng), n01(rng)));
    cam.fovYDeg = 20.0f + 70.0f * u01(rng);
    cam.projection = ortho ? Projection::Orthographic : Projection::Perspective;
    cam.orthoHeight = 1.0f + 3.0f * u01(rng);
    return cam;
}

RoundedCone randomCone(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
    std::normal_distribution<float> n01;
    auto logUniform = [&](float lo, float hi) { return lo * std::pow(hi / lo, u01(rng)); };
    RoundedCone c;
    c.x0 = {0.7f * u(rng), 0.7f * u(rng), 0.7f * u(rng)};
    c.r0 = logUniform(1e-3f, 0.2f);
    c.r1 = u01(rng) < 0.3f ? c.r0 : logUniform(1e-3f, 0.2f);
    c.x1 = c.x0 + glm::normalize(glm::vec3(n01(rng), n01(rng), n01(rng))) * logUniform(1e-3f, 1.0f);
    return c;
}

// Tightness bound: the quad is the rectangle around the two ends' tangent-cone discs (their
// bounding squares' projections). For a sphere-like cone that is a square around a disc, 4/pi =
// 1.27; a long tube approaches 1; the worst is a cone with r0 << r1 seen side-on (rectangle over
// a trapezoid-like hull, < 2) and strong perspective stretches at the image border. The mean is
// what matters for cost.
constexpr double kMeanRatioBound = 1.6;
constexpr double kMaxRatioBound = 2.5;

TEST(Billboard, contains_all_projected_surface_points_perspective) {
    std::mt19937 rng(1);
    Stats st;
    for (int i = 0; i < 500; ++i) checkContainment(randomCone(rng), randomCamera(rng, false), rng, st, true);
    std::printf("perspective: %d quads, mean area ratio %.3f, max %.3f\n", st.quads, st.ratioSum / st.quads,
                st.ratioMax);
    EXPECT_EQ(st.quads, 500);
    EXPECT_LT(st.ratioSum / st.quads, kMeanRatioBound);
    EXPECT_LT(st.ratioMax, kMaxRatioBound);
}

TEST(Billboard, contains_all_projected_surface_points_orthographic) {
    std::mt19937 rng(2);
    Stats st;
    for (int i = 0; i < 500; ++i) checkContainment(randomCone(rng), randomCamera(rng, true), rng, st, true);
    std::printf("orthographic: %d quads, mean area ratio %.3f, max %.3f\n", st.quads, st.ratioSum / st.quads,
                st.ratioMax);
    EXPECT_EQ(st.quads, 500);
    EXPECT_LT(st.ratioSum / st.quads, kMeanRatioBound);
    EXPECT_LT(st.ratioMax, kMaxRatioBound);
}

TEST(Billboard, contains_cones_near_the_eye_and_far_away) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    Stats st;
    for (int i = 0; i < 400; ++i) {
        Camera cam = randomCamera(rng, i % 2 == 1);
        RoundedCone c = randomCone(rng);
        // Move the cone along the view ray: close to the eye (just outside) or far.
        glm::vec3 f = cam.forward();
        float dist = i % 4 < 2 ? 2.5f * glm::max(c.r0, c.r1) + glm::length(c.x1 - c.x0) + 0.05f * u01(rng) : 20.0f;
        glm::vec3 shift = cam.eye + f * dist - 0.5f * (c.x0 + c.x1);
        c.x0 += shift, c.x1 += shift;
        checkContainment(c, cam, rng, st, false);
    }
    std::printf("near/far: %d quads, %d full screen, %d culled\n", st.quads, st.fullscreen, st.culled);
    EXPECT_GT(st.quads, 200);
}

TEST(Billboard, degenerate_views_give_valid_quads_without_nan) {
    std::mt19937 rng(4);
    Stats st;
    RoundedCone c{{0, 0, 0}, 0.1f, {1, 0, 0}, 0.05f};
    auto camAt = [](glm::vec3 eye, glm::vec3 target, bool ortho) {
        Camera cam;
        cam.eye = eye;
        cam.target = target;
        cam.projection = ortho ? Projection::Orthographic : Projection::Perspective;
        return cam;
    };
    for (bool ortho : {false, true}) {
        // Eye inside sphere 0, inside the tube, on the axis looking along it (outside), the
        // segment crossing the eye plane, the cone behind the eye.
        for (Camera cam : {camAt({0.02f, 0.01f, 0}, {0, 0, -1}, ortho), camAt({0.5f, 0.0f, 0.01f}, {0.5f, 1, 0}, ortho),
                           camAt({-2, 0, 0}, {0, 0, 0}, ortho), camAt({3, 0, 0}, {0, 0, 0}, ortho),
                           camAt({0.5f, 0, 2}, {0.5f, 3, 2}, ortho), camAt({0.5f, 1, 0}, {0.5f, 2, 0}, ortho),
                           camAt({0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 1.5f}, ortho)}) {
            checkContainment(c, cam, rng, st, false);
        }
    }
    std::printf("degenerate: %d quads, %d full screen, %d culled\n", st.quads, st.fullscreen, st.culled);
    EXPECT_GE(st.culled, 1);
    EXPECT_GE(st.fullscreen, 2);
}

TEST(Billboard, view_along_the_axis_gives_a_tight_containing_quad) {
    std::mt19937 rng(5);
    Stats st;
    RoundedCone c{{0, 0, 0}, 0.1f, {0, 0, -1}, 0.05f};
    Camera cam;
    cam.eye = {0, 0, 3};
    cam.target = {0, 0, 0};
    checkContainment(c, cam, rng, st, true);
    cam.projection = Projection::Orthographic;
    checkContainment(c, cam, rng, st, true);
    EXPECT_EQ(st.quads, 2);
    EXPECT_LT(st.ratioMax, 1.5);
}

}  // namespace
}  // namespace tc
