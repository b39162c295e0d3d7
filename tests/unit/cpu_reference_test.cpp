// The CPU reference against analytic images: depth profile and normals of a cylinder seen
// orthographically, ids, background, nearest-wins and tie order.
#include "core/cpu_reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/shading.h"

namespace tc {
namespace {

StyledLines makeLines(const std::vector<std::pair<glm::vec4, glm::vec4>>& segments,
                      const std::vector<std::uint32_t>& ids, glm::vec4 color0 = {0.8f, 0.4f, 0.2f, 1.0f},
                      glm::vec4 color1 = {0.8f, 0.4f, 0.2f, 1.0f}) {
    StyledLines l;
    for (std::size_t s = 0; s < segments.size(); ++s) {
        l.positionRadius.push_back(segments[s].first);
        l.positionRadius.push_back(segments[s].second);
        l.color.push_back(color0);
        l.color.push_back(color1);
        l.polylineId.push_back(ids[s]);
        l.polylineId.push_back(ids[s]);
        l.flags.push_back(FirstOfPolyline);
        l.flags.push_back(LastOfPolyline);
        l.segmentVertices.push_back(std::uint32_t(2 * s));
        l.segmentVertices.push_back(std::uint32_t(2 * s + 1));
        l.maxRadius = std::max({l.maxRadius, segments[s].first.w, segments[s].second.w});
    }
    return l;
}

void expectBackground(const FrameImages& img, std::size_t i) {
    EXPECT_EQ(img.depth[i], std::numeric_limits<float>::infinity());
    EXPECT_EQ(img.id[i], kBackgroundId);
    for (int c = 0; c < 4; ++c) EXPECT_EQ(img.rgba[4 * i + c], 0.0f);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(img.normal[3 * i + c], 0.0f);
}

TEST(Shading, specular_power_is_pow_within_the_rounding_of_its_products) {
    // A whole exponent e by repeated squaring: each of the at most 2 log2(e) float products rounds
    // by at most 2^-24 relative, and the errors of x^(2^k) add up to below e x 2^-24; checked
    // with twice that margin against double pow, plus an absolute slack for results in float's
    // denormal range. Other exponents are std::pow itself.
    std::mt19937 rng(3u);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> xs = {0.0f, 1.0f, 1e-20f, 0.5f, 0.999999f, std::nextafter(1.0f, 0.0f)};
    for (int i = 0; i < 2000; ++i) xs.push_back(i % 2 ? u(rng) : 1.0f - 1e-3f * u(rng));  // and near the peak
    for (int e : {1, 2, 3, 5, 8, 31, 32, 33, 100, 777, 1024}) {
        for (float x : xs) {
            const double exact = std::pow(double(x), double(e));
            const double got = specularPower(x, float(e));
            ASSERT_LE(std::abs(got - exact), 2.0 * e * std::ldexp(1.0, -24) * exact + 1e-37) << "x " << x << " e " << e;
        }
    }
    EXPECT_EQ(specularPower(0.37f, 1.0f), 0.37f);
    for (float e : {0.5f, 2.5f, 32.1f, 1025.0f, 5000.0f})
        for (float x : {0.0f, 0.2f, 0.9f, 1.0f}) EXPECT_EQ(specularPower(x, e), std::pow(x, e)) << x << " " << e;
}

TEST(CpuReference, orthographic_cylinder_has_analytic_depth_profile_and_normals) {
    const float r = 0.1f, d = 3.0f;
    StyledLines lines = makeLines({{{-2, 0, 0, r}, {2, 0, 0, r}}}, {7});
    Camera cam;
    cam.eye = {0, 0, d};
    cam.target = {0, 0, 0};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 0.5f;
    LightingSpec light;
    const int w = 24, h = 64;
    FrameImages img = renderReferenceOpaque(lines, cam, light, w, h);
    ASSERT_EQ(img.width, w);
    int covered = 0;
    for (int py = 0; py < h; ++py) {
        float y = (1.0f - 2.0f * (py + 0.5f) / h) * 0.5f * cam.orthoHeight;
        for (int px = 0; px < w; ++px) {
            std::size_t i = std::size_t(py) * w + px;
            if (std::abs(y) > r * 1.001f) {
                expectBackground(img, i);
                continue;
            }
            if (std::abs(y) > 0.98f * r) continue;  // silhouette: depth is ill-conditioned there
            ++covered;
            float z = std::sqrt(r * r - y * y);
            EXPECT_NEAR(img.depth[i], d - z, 1e-5f) << px << "," << py;
            glm::vec3 n(img.normal[3 * i], img.normal[3 * i + 1], img.normal[3 * i + 2]);
            glm::vec3 expected = glm::vec3(0, y, z) / r;
            EXPECT_LT(glm::length(n - expected), 1e-3f) << px << "," << py;
            EXPECT_EQ(img.id[i], 7u);
            EXPECT_EQ(img.rgba[4 * i + 3], 1.0f);
            glm::vec3 shaded =
                shadeBlinnPhong({0.8f, 0.4f, 0.2f}, expected, {0, 0, -1}, lightDirectionWorld(light, cam), light);
            EXPECT_NEAR(img.rgba[4 * i + 0], shaded.x, 2e-3f);
            EXPECT_NEAR(img.rgba[4 * i + 1], shaded.y, 2e-3f);
            EXPECT_NEAR(img.rgba[4 * i + 2], shaded.z, 2e-3f);
        }
    }
    EXPECT_GT(covered, 10 * w);
}

TEST(CpuReference, sphere_like_segment_at_the_centre_has_its_polyline_id_and_background_elsewhere) {
    StyledLines lines = makeLines({{{0, 0, 0, 0.2f}, {1e-4f, 0, 0, 0.2f}}}, {42});
    Camera cam;  // perspective, eye (0,0,3) looking at the origin
    const int w = 33, h = 33;
    FrameImages img = renderReferenceOpaque(lines, cam, LightingSpec{}, w, h);
    std::size_t centre = 16 * w + 16;
    EXPECT_EQ(img.id[centre], 42u);
    EXPECT_NEAR(img.depth[centre], 2.8f, 1e-5f);
    EXPECT_NEAR(img.normal[3 * centre + 2], 1.0f, 1e-5f);
    for (std::size_t corner : {std::size_t(0), std::size_t(w - 1), std::size_t(w * (h - 1)), std::size_t(w * h - 1)})
        expectBackground(img, corner);
}

TEST(CpuReference, nearest_tube_wins_and_ties_keep_the_lower_segment_index) {
    Camera cam;
    // Segment 0 behind segment 1 (nearer wins); segments 2 and 3 identical (first drawn wins).
    StyledLines lines = makeLines({{{-1, 0.3f, -0.5f, 0.05f}, {1, 0.3f, -0.5f, 0.05f}},
                                   {{-1, 0.3f, 0.5f, 0.05f}, {1, 0.3f, 0.5f, 0.05f}},
                                   {{-1, -0.3f, 0, 0.05f}, {1, -0.3f, 0, 0.05f}},
                                   {{-1, -0.3f, 0, 0.05f}, {1, -0.3f, 0, 0.05f}}},
                                  {10, 11, 12, 13});
    const int w = 32, h = 32;
    FrameImages img = renderReferenceOpaque(lines, cam, LightingSpec{}, w, h);
    int seen11 = 0, seen12 = 0;
    for (std::size_t i = 0; i < img.pixelCount(); ++i) {
        EXPECT_NE(img.id[i], 13u);
        seen11 += img.id[i] == 11u;
        seen12 += img.id[i] == 12u;
    }
    EXPECT_GT(seen11, 10);
    EXPECT_GT(seen12, 10);
}

TEST(CpuReference, colour_is_interpolated_along_the_segment) {
    StyledLines lines = makeLines({{{-0.5f, 0, 0, 0.1f}, {0.5f, 0, 0, 0.1f}}}, {0}, {1, 0, 0, 1}, {0, 0, 1, 1});
    Camera cam;
    cam.projection = Projection::Orthographic;
    const int w = 41, h = 41;
    FrameImages img = renderReferenceOpaque(lines, cam, LightingSpec{}, w, h);
    std::size_t centre = 20 * w + 20;
    ASSERT_EQ(img.id[centre], 0u);
    EXPECT_NEAR(img.rgba[4 * centre + 0], img.rgba[4 * centre + 2], 1e-5f);  // half red, half blue
    std::size_t left = 20 * w + 12, right = 20 * w + 28;
    EXPECT_GT(img.rgba[4 * left + 0], img.rgba[4 * left + 2]);
    EXPECT_LT(img.rgba[4 * right + 0], img.rgba[4 * right + 2]);
}

TEST(CpuReference, eye_inside_a_tube_sees_the_inner_wall) {
    StyledLines lines = makeLines({{{0, 0, -5, 0.5f}, {0, 0, 5, 0.5f}}}, {3});
    Camera cam;
    cam.eye = {0, 0, 0};
    cam.target = {0, 1, 0};
    cam.up = {0, 0, 1};
    FrameImages img = renderReferenceOpaque(lines, cam, LightingSpec{}, 9, 9);
    std::size_t centre = 4 * 9 + 4;
    EXPECT_EQ(img.id[centre], 3u);
    EXPECT_NEAR(img.depth[centre], 0.5f, 1e-5f);
    EXPECT_NEAR(img.normal[3 * centre + 1], 1.0f, 1e-5f);  // outward normal of the wall
    EXPECT_GT(img.rgba[4 * centre + 3], 0.0f);
}

}  // namespace
}  // namespace tc
