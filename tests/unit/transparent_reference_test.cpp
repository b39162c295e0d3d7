// The transparent CPU reference against analytic compositing: coverage alpha of one tube, "front
// over back" colour of two crossing tubes, order-independent alpha 1 - prod(1 - a_i), and the
// opaque limit (alpha 1) reproducing renderReferenceOpaque (colour clamped to [0, 1], as every
// transparent path blends it).
#include "core/transparent_reference.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/cpu_reference.h"
#include "core/rounded_cone.h"

namespace tc {
namespace {

struct Tube {
    glm::vec4 a, b;   // xyz, radius
    glm::vec4 color;  // rgb, alpha (both vertices)
};

// One single-segment polyline per tube, in the given order.
StyledLines makeLines(const std::vector<Tube>& tubes) {
    StyledLines l;
    for (std::size_t s = 0; s < tubes.size(); ++s) {
        l.positionRadius.push_back(tubes[s].a);
        l.positionRadius.push_back(tubes[s].b);
        l.color.push_back(tubes[s].color);
        l.color.push_back(tubes[s].color);
        l.polylineId.push_back(std::uint32_t(s));
        l.polylineId.push_back(std::uint32_t(s));
        l.flags.push_back(FirstOfPolyline);
        l.flags.push_back(LastOfPolyline);
        l.segmentVertices.push_back(std::uint32_t(2 * s));
        l.segmentVertices.push_back(std::uint32_t(2 * s + 1));
        l.maxRadius = std::max({l.maxRadius, tubes[s].a.w, tubes[s].b.w});
    }
    return l;
}

Camera frontCamera(Projection projection) {
    Camera cam;
    cam.eye = {0.0f, 0.0f, 3.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.projection = projection;
    cam.orthoHeight = 2.0f;
    return cam;
}

// The opaque reference's colour as the transparent paths blend it: clamped to [0, 1].
float clamped(const FrameImages& img, std::size_t i, int c) {
    return std::clamp(img.rgba[4 * i + c], 0.0f, 1.0f);
}

glm::vec4 pixel(const FrameImages& img, std::size_t i) {
    return {img.rgba[4 * i], img.rgba[4 * i + 1], img.rgba[4 * i + 2], img.rgba[4 * i + 3]};
}

TEST(TransparentReference, single_tube_has_alpha_a_where_covered_and_is_a_times_the_opaque_image) {
    const float a = 0.35f;
    for (Projection projection : {Projection::Orthographic, Projection::Perspective}) {
        StyledLines l = makeLines({{{-0.8f, -0.3f, 0.1f, 0.15f}, {0.7f, 0.4f, -0.2f, 0.25f}, {0.2f, 0.6f, 0.9f, a}}});
        StyledLines opaqueLines = l;
        for (glm::vec4& c : opaqueLines.color) c.w = 1.0f;
        Camera cam = frontCamera(projection);
        LightingSpec light;
        const int w = 48, h = 40;
        std::vector<int> counts;
        FrameImages t = renderReferenceTransparent(l, cam, light, w, h, true, &counts);
        FrameImages o = renderReferenceOpaque(opaqueLines, cam, light, w, h);
        int covered = 0;
        for (std::size_t i = 0; i < t.pixelCount(); ++i) {
            if (o.id[i] == kBackgroundId) {
                EXPECT_EQ(pixel(t, i), glm::vec4(0.0f)) << i;
                EXPECT_EQ(counts[i], 0);
                continue;
            }
            ++covered;
            EXPECT_EQ(counts[i], 1) << i;
            EXPECT_NEAR(t.rgba[4 * i + 3], a, 1e-6f) << i;
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(t.rgba[4 * i + c], a * clamped(o, i, c), 1e-6f) << i;
            EXPECT_EQ(t.depth[i], o.depth[i]);
            EXPECT_EQ(t.id[i], o.id[i]);
        }
        EXPECT_GT(covered, 100);
    }
}

TEST(TransparentReference, two_crossing_tubes_composite_front_over_back_whatever_their_segment_order) {
    // Red in front (z = +0.5) along x, green behind (z = -0.5) along y; they overlap around the
    // image centre. Expected: C = a1 c1 + (1 - a1) a2 c2, A = a1 + (1 - a1) a2, with c1, c2 the
    // shaded colours the opaque reference gives each tube alone.
    const Tube front{{-1, 0, 0.5f, 0.2f}, {1, 0, 0.5f, 0.2f}, {1.0f, 0.1f, 0.1f, 0.4f}};
    const Tube back{{0, -1, -0.5f, 0.2f}, {0, 1, -0.5f, 0.2f}, {0.1f, 1.0f, 0.1f, 0.6f}};
    Camera cam = frontCamera(Projection::Orthographic);
    LightingSpec light;
    const int w = 32, h = 32;
    auto opaque = [&](Tube t) {
        t.color.w = 1.0f;
        return renderReferenceOpaque(makeLines({t}), cam, light, w, h);
    };
    FrameImages o1 = opaque(front), o2 = opaque(back);
    int overlap = 0;
    for (const std::vector<Tube>& order : {std::vector<Tube>{front, back}, std::vector<Tube>{back, front}}) {
        FrameImages img = renderReferenceTransparent(makeLines(order), cam, light, w, h, true);
        const std::uint32_t frontId = order[0].color == front.color ? 0u : 1u;
        overlap = 0;
        for (std::size_t i = 0; i < img.pixelCount(); ++i) {
            if (o1.id[i] == kBackgroundId || o2.id[i] == kBackgroundId) continue;
            ++overlap;
            const float a1 = front.color.w, a2 = back.color.w;
            for (int c = 0; c < 3; ++c) {
                float expected = a1 * clamped(o1, i, c) + (1 - a1) * a2 * clamped(o2, i, c);
                EXPECT_NEAR(img.rgba[4 * i + c], expected, 1e-6f) << i;
            }
            EXPECT_NEAR(img.rgba[4 * i + 3], a1 + (1 - a1) * a2, 1e-6f);
            // depth / normal / id of the nearest fragment: the front tube's.
            EXPECT_EQ(img.depth[i], o1.depth[i]);
            EXPECT_EQ(img.id[i], frontId);
        }
    }
    EXPECT_GT(overlap, 9);
}

// Random crossing tubes with random alphas; constant colour per tube.
std::vector<Tube> randomTubes(unsigned seed, int n, float alphaLo, float alphaHi) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-0.8f, 0.8f), rad(0.05f, 0.2f), col(0.0f, 1.0f), alpha(alphaLo, alphaHi);
    std::vector<Tube> tubes;
    for (int i = 0; i < n; ++i)
        tubes.push_back({{pos(rng), pos(rng), pos(rng), rad(rng)},
                         {pos(rng), pos(rng), pos(rng), rad(rng)},
                         {col(rng), col(rng), col(rng), alpha(rng)}});
    return tubes;
}

TEST(TransparentReference, alpha_is_one_minus_the_product_of_one_minus_alpha_in_any_order) {
    std::vector<Tube> tubes = randomTubes(7u, 12, 0.1f, 0.7f);
    StyledLines l = makeLines(tubes);
    LightingSpec light;
    const int w = 40, h = 40;
    Camera cam = frontCamera(Projection::Orthographic);
    Camera behind = cam;  // the same rays, mirrored left-right, traversed back to front
    behind.eye = {0.0f, 0.0f, -3.0f};
    FrameImages img = renderReferenceTransparent(l, cam, light, w, h, false);
    FrameImages rev = renderReferenceTransparent(l, behind, light, w, h, false);
    std::vector<Tube> shuffled = tubes;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3u));
    FrameImages shuf = renderReferenceTransparent(makeLines(shuffled), cam, light, w, h, false);

    int multi = 0, colourDiffers = 0;
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            std::size_t i = std::size_t(py) * w + px;
            // Independent: every tube the ray enters (or starts in), any order.
            Ray ray = pixelRay(cam, w, h, float(px), float(py));
            float transmit = 1.0f;
            int hits = 0;
            for (const Tube& t : tubes) {
                ConeInterval c = intersectRoundedCone(ray, {glm::vec3(t.a), t.a.w, glm::vec3(t.b), t.b.w});
                if (c.hit && c.tOut > 0.0f) transmit *= 1.0f - t.color.w, ++hits;
            }
            multi += hits >= 2;
            EXPECT_NEAR(img.rgba[4 * i + 3], 1.0f - transmit, 1e-5f) << px << "," << py;
            std::size_t j = std::size_t(py) * w + (w - 1 - px);
            EXPECT_NEAR(rev.rgba[4 * j + 3], img.rgba[4 * i + 3], 1e-5f) << px << "," << py;
            EXPECT_EQ(pixel(shuf, i), pixel(img, i)) << px << "," << py;  // sorted: buffer order is irrelevant
            colourDiffers += glm::length(glm::vec3(pixel(rev, j)) - glm::vec3(pixel(img, i))) > 1e-2f;
        }
    EXPECT_GT(multi, 100);
    EXPECT_GT(colourDiffers, 50);  // colour does depend on the order: the test sees real overlaps
}

TEST(TransparentReference, opaque_limit_equals_the_opaque_reference) {
    std::vector<Tube> tubes = randomTubes(11u, 10, 1.0f, 1.0f);
    StyledLines l = makeLines(tubes);
    LightingSpec light;
    const int w = 40, h = 30;
    for (Projection projection : {Projection::Orthographic, Projection::Perspective}) {
        Camera cam = frontCamera(projection);
        cam.eye = {0.7f, 0.9f, 2.8f};
        FrameImages t = renderReferenceTransparent(l, cam, light, w, h, false);
        FrameImages o = renderReferenceOpaque(l, cam, light, w, h);
        int covered = 0;
        for (std::size_t i = 0; i < t.pixelCount(); ++i) {
            covered += o.id[i] != kBackgroundId;
            EXPECT_EQ(t.depth[i], o.depth[i]) << i;
            EXPECT_EQ(t.id[i], o.id[i]) << i;
            for (int c = 0; c < 3; ++c) EXPECT_EQ(t.normal[3 * i + c], o.normal[3 * i + c]) << i;
            // Interpolated alpha mix(1, 1, u) may round to 1 - 2^-24: near, not equal.
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(t.rgba[4 * i + c], clamped(o, i, c), 1e-6f) << i;
            EXPECT_NEAR(t.rgba[4 * i + 3], o.rgba[4 * i + 3], 1e-6f) << i;
        }
        EXPECT_GT(covered, 200);
    }
}

TEST(TransparentReference, opaque_limit_of_a_cap_clipped_polyline_shows_the_same_tube) {
    // A bent constant-radius polyline: with cap clipping the nearest fragment is the union's
    // first entry, the same surface the opaque reference sees (depth to 1e-5, normal to 1e-3).
    StyledLines l;
    const glm::vec3 p[] = {{-0.9f, -0.3f, 0.0f}, {-0.3f, 0.1f, 0.2f}, {0.2f, -0.2f, 0.0f}, {0.8f, 0.3f, -0.1f}};
    for (int i = 0; i < 4; ++i) {
        l.positionRadius.emplace_back(p[i], 0.15f);
        l.color.emplace_back(0.3f, 0.6f, 0.9f, 1.0f);
        l.polylineId.push_back(5u);
        l.flags.push_back(i == 0 ? FirstOfPolyline : i == 3 ? LastOfPolyline : 0u);
        if (i > 0) l.segmentVertices.insert(l.segmentVertices.end(), {std::uint32_t(i - 1), std::uint32_t(i)});
    }
    Camera cam = frontCamera(Projection::Perspective);
    cam.eye = {0.4f, 1.2f, 2.6f};
    LightingSpec light;
    const int w = 48, h = 36;
    std::vector<int> counts;
    FrameImages t = renderReferenceTransparent(l, cam, light, w, h, true, &counts);
    FrameImages o = renderReferenceOpaque(l, cam, light, w, h);
    int covered = 0;
    for (std::size_t i = 0; i < t.pixelCount(); ++i) {
        ASSERT_EQ(t.id[i], o.id[i]) << i;
        if (o.id[i] == kBackgroundId) continue;
        ++covered;
        EXPECT_NEAR(t.depth[i], o.depth[i], 1e-5f) << i;
        glm::vec3 nt(t.normal[3 * i], t.normal[3 * i + 1], t.normal[3 * i + 2]);
        glm::vec3 no(o.normal[3 * i], o.normal[3 * i + 1], o.normal[3 * i + 2]);
        EXPECT_LT(glm::length(nt - no), 1e-3f) << i;
        EXPECT_NEAR(t.rgba[4 * i + 3], 1.0f, 1e-6f);
    }
    EXPECT_GT(covered, 150);
    EXPECT_GE(*std::max_element(counts.begin(), counts.end()), 1);
}

}  // namespace
}  // namespace tc
