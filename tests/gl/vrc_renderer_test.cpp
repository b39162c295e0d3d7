// Voxel-based line ray casting (gl/vrc_renderer.h) against the rasterized rounded-cone paths on
// straight tubes, where VRC with exact ends (quantization 0) and neighbour tests (or copies into
// the neighbours, the default) is exact: the pieces of a straight tube are collinear sub-cones
// whose union is the tube, and every piece whose tube reaches into a voxel is tested there when
// radius < voxel size.
//   - opaque: view depth, polyline id and colour == the opaque rounded-cone renderer
//     (gl/rounded_cone_renderer.h);
//   - transparent: colour and alpha == depth peeling of the same tubes (non-intersecting, so the
//     per-ray order of the tubes is the same in both).
// Pixels on silhouettes (3x3 neighbourhood with a different coverage / fragment set) are excluded:
// one ray more or less through a rim is float noise, not method.
#include "gl/vrc_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/error.h"
#include "core/scene.h"
#include "core/technique.h"
#include "core/vrc_model.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

// Non-intersecting straight tubes crossing each other in screen space at different depths: three
// along x, three along y (one tapered, one a straight polyline of 5 collinear vertices), depths
// separated by more than the sum of radii. Radii < voxel size at resolution 24 (voxel ~0.1).
StyledLines straightTubes(float alpha) {
    std::vector<TestPolyline> p;
    auto tube = [&](glm::vec3 a, glm::vec3 b, float ra, float rb, glm::vec3 rgb, int vertices = 2) {
        TestPolyline pl;
        for (int i = 0; i < vertices; ++i) {
            const float s = float(i) / float(vertices - 1);
            pl.push_back({glm::mix(a, b, s), ra + (rb - ra) * s, glm::vec4(rgb, alpha)});
        }
        p.push_back(pl);
    };
    tube({-1.0f, -0.5f, -0.6f}, {1.0f, -0.45f, -0.6f}, 0.06f, 0.06f, {0.9f, 0.2f, 0.1f});
    tube({-1.0f, 0.0f, 0.0f}, {1.0f, 0.1f, 0.05f}, 0.05f, 0.08f, {0.2f, 0.8f, 0.3f});
    tube({-1.0f, 0.5f, 0.5f}, {1.0f, 0.45f, 0.55f}, 0.07f, 0.07f, {0.2f, 0.3f, 0.9f}, 5);
    tube({-0.6f, -1.0f, -0.3f}, {-0.55f, 1.0f, -0.3f}, 0.05f, 0.05f, {0.9f, 0.9f, 0.2f});
    tube({0.0f, -1.0f, 0.3f}, {0.05f, 1.0f, 0.3f}, 0.06f, 0.06f, {0.8f, 0.3f, 0.8f}, 4);
    tube({0.6f, -1.0f, 0.8f}, {0.62f, 1.0f, 0.75f}, 0.04f, 0.07f, {0.3f, 0.9f, 0.9f});
    return makeStyledLines(p);
}

Camera obliqueCamera() {
    Camera cam;
    cam.eye = {0.7f, 0.5f, 2.3f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 45.0f;
    return cam;
}

Scene comparedVrcScene(int w, int h, bool transparent, int quantization, bool neighbors) {
    Scene scene = vrcScene(w, h, 24, transparent ? Transparency::KBuffer : Transparency::Opaque);
    scene.render.vrc.quantization = quantization;
    scene.render.vrc.neighbors = neighbors;
    scene.render.vrc.opacityThreshold = 1.0f;  // no early termination: compare the full composite
    return scene;
}

FrameImages render(tc::Technique& t, const Scene& scene, const Camera& cam) {
    gl::StageTimer timer;
    FrameImages out;
    t.render(tc::FrameSetup{0, cam, scene.image.width, scene.image.height}, out, timer);
    timer.collect();
    return out;
}

FrameImages render(const Scene& scene, const StyledLines& lines, const Camera& cam) {
    std::unique_ptr<tc::Technique> t = gl::createTechnique(scene, lines);
    return render(*t, scene, cam);
}

// Rasterized depth peeling of `lines` (with `halo`'s rings if enabled), colour only: the exact
// reference of the ray caster.
FrameImages depthPeeled(const StyledLines& lines, const Camera& cam, int w, int h, const HaloSpec& halo = {}) {
    Scene peel;
    peel.image.width = w;
    peel.image.height = h;
    peel.render.transparency = Transparency::DepthPeeling;
    peel.output.aovDepth = peel.output.aovNormal = peel.output.aovId = false;
    peel.style.halo = halo;
    return render(peel, lines, cam);
}

// 3x3 neighbourhood of (x, y) holds a value of key() different from (x, y)'s.
template <class Key>
bool onEdge(int w, int h, int x, int y, Key key) {
    const auto k = key(x, y);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int u = x + dx, v = y + dy;
            if (u >= 0 && v >= 0 && u < w && v < h && key(u, v) != k) return true;
        }
    return false;
}

TEST_F(GlTest, vrc_model_voxel_size_exceeds_the_test_tubes_radii) {
    // The premise of the exactness tests below.
    const StyledLines lines = straightTubes(1.0f);
    VrcBuildOptions o;
    o.resolution = 24;
    o.quantization = 0;
    const VrcModel m = buildVrcModel(lines, o);
    EXPECT_GT(m.voxelSize, lines.maxRadius);
    EXPECT_GT(m.pieceCount(), 6u * 10u);  // every tube is cut into many pieces
}

TEST_F(GlTest, vrc_run_json_reports_the_largest_tube_radius_in_voxels) {
    // Tubes wider than a voxel are cut one voxel out (docs/scene-spec.md, vrc.neighbors):
    // max_radius_voxels says whether a model is in the exact regime (< 1), halo.max_ring_radius_voxels
    // the same for the rings.
    const StyledLines lines = straightTubes(1.0f);
    for (int resolution : {24, 128}) {
        Scene scene = comparedVrcScene(16, 16, false, 32, false);
        scene.render.vrc.resolution = resolution;
        const std::unique_ptr<tc::Technique> t = gl::createTechnique(scene, lines);
        const nlohmann::json d = t->describe();
        const double expected = double(lines.maxRadius) / d.at("voxel_size").get<double>();
        EXPECT_NEAR(d.at("max_radius_voxels").get<double>(), expected, 1e-6 * expected);
        EXPECT_EQ(d.at("max_radius_voxels").get<double>() < 1.0, resolution == 24) << resolution;
        EXPECT_EQ(d.at("halo"), false);
        // With halos, the ring's radius in voxels (it must fit one voxel as the tubes).
        scene.render.transparency = Transparency::DepthPeeling;
        scene.style.halo.enabled = true;
        scene.style.halo.width = 0.5f;
        const nlohmann::json ringed = gl::createTechnique(scene, lines)->describe();
        EXPECT_NEAR(ringed.at("halo").at("max_ring_radius_voxels").get<double>(), 1.5 * expected, 1e-6 * expected);
    }
}

TEST_F(GlTest, vrc_opaque_depth_id_and_colour_match_rasterized_rounded_cones_on_straight_tubes) {
    const int w = 128, h = 96;
    const StyledLines lines = straightTubes(1.0f);
    const Camera cam = obliqueCamera();
    Scene raster;
    raster.image.width = w;
    raster.image.height = h;
    const FrameImages ref = render(raster, lines, cam);
    // Neighbour tests at render time, or copies into the neighbours at build time (the default):
    // both test every piece whose tube reaches into the voxel.
    for (bool neighbors : {true, false}) {
        SCOPED_TRACE(neighbors ? "neighbors on" : "neighbors off (copies)");
        const FrameImages vrc = render(comparedVrcScene(w, h, false, 0, neighbors), lines, cam);
        ASSERT_EQ(vrc.depth.size(), ref.depth.size());
        auto refId = [&](int x, int y) { return ref.id[std::size_t(y) * w + x]; };
        std::size_t compared = 0, coverageOff = 0, idOff = 0, depthOff = 0, colorOff = 0;
        double worstDepth = 0, worstColor = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (onEdge(w, h, x, y, refId)) continue;
                const std::size_t i = std::size_t(y) * w + x;
                const bool rh = ref.id[i] != kBackgroundId, vh = vrc.id[i] != kBackgroundId;
                if (rh != vh) {
                    ++coverageOff;
                    continue;
                }
                if (!rh) {
                    EXPECT_TRUE(std::isinf(vrc.depth[i]));
                    continue;
                }
                ++compared;
                idOff += ref.id[i] != vrc.id[i];
                // Same intersector on collinear sub-cones: float noise of t0 only (see
                // rounded_cone_renderer_test.cpp, 1e-5 there); 1e-4 relative still catches a wrong
                // piece or surface (>= 1e-2 here).
                const double dd = std::abs(double(ref.depth[i]) - vrc.depth[i]) / ref.depth[i];
                worstDepth = std::max(worstDepth, dd);
                depthOff += dd > 1e-4;
                // The rasterized G-buffer stores albedo in RGBA16F (<= 4.9e-4 relative).
                for (int c = 0; c < 4; ++c) {
                    const double dc = std::abs(double(ref.rgba[4 * i + c]) - vrc.rgba[4 * i + c]);
                    worstColor = std::max(worstColor, dc);
                    colorOff += dc > 2e-3;
                }
            }
        std::printf("vrc opaque vs rasterized: %zu px compared, worst depth rel %.3g, worst colour %.3g\n", compared,
                    worstDepth, worstColor);
        EXPECT_GT(compared, std::size_t(w * h / 10));
        EXPECT_EQ(coverageOff, 0u);
        EXPECT_EQ(idOff, 0u);
        EXPECT_EQ(depthOff, 0u) << "worst " << worstDepth;
        EXPECT_EQ(colorOff, 0u) << "worst " << worstColor;
    }
}

TEST_F(GlTest, vrc_without_neighbor_tests_or_copies_cuts_tubes_at_voxel_faces) {
    // The reason for render.vrc.neighbors and the copies: tubes that stick out of the voxels
    // holding their axis lose those parts when only the current voxel's own pieces are tested.
    const int w = 96, h = 72;
    const StyledLines lines = straightTubes(1.0f);
    const Camera cam = obliqueCamera();
    const FrameImages on = render(comparedVrcScene(w, h, false, 0, true), lines, cam);
    VrcBuildOptions o;
    o.resolution = 24;
    o.quantization = 0;
    o.dilate = false;
    const Scene offScene = comparedVrcScene(w, h, false, 0, false);
    const std::unique_ptr<gl::VrcRenderer> plain = gl::VrcRenderer::create(offScene, lines, buildVrcModel(lines, o));
    const FrameImages off = render(*plain, offScene, cam);
    std::size_t hitsOn = 0, hitsOff = 0, offOnly = 0;
    for (std::size_t i = 0; i < on.id.size(); ++i) {
        hitsOn += on.id[i] != kBackgroundId;
        hitsOff += off.id[i] != kBackgroundId;
        offOnly += off.id[i] != kBackgroundId && on.id[i] == kBackgroundId;
    }
    EXPECT_LT(hitsOff, hitsOn);
    EXPECT_EQ(offOnly, 0u);  // a subset: hits are only ever accepted inside the current voxel
}

TEST_F(GlTest, vrc_transparent_matches_depth_peeling_on_non_intersecting_straight_tubes) {
    const int w = 128, h = 96;
    const StyledLines lines = straightTubes(0.4f);
    const Camera cam = obliqueCamera();
    const FrameImages ref = depthPeeled(lines, cam, w, h);
    for (bool neighbors : {true, false}) {
        SCOPED_TRACE(neighbors ? "neighbors on" : "neighbors off (copies)");
        const FrameImages vrc = render(comparedVrcScene(w, h, true, 0, neighbors), lines, cam);
        ASSERT_EQ(vrc.rgba.size(), ref.rgba.size());
        // Alpha is piecewise constant (1 - 0.6^layers): an edge is where it changes.
        auto layers = [&](int x, int y) { return int(std::lround(ref.rgba[4 * (std::size_t(y) * w + x) + 3] * 1000)); };
        std::size_t compared = 0, multi = 0, alphaOff = 0, colorOff = 0;
        double worstAlpha = 0, worstColor = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (onEdge(w, h, x, y, layers)) continue;
                const std::size_t i = std::size_t(y) * w + x;
                ++compared;
                multi += ref.rgba[4 * i + 3] > 0.5f;  // two or more tubes
                // Alpha: 1 - prod(1 - a) over the same fragments in fp32 (1e-5: a few ulps).
                const double da = std::abs(double(ref.rgba[4 * i + 3]) - vrc.rgba[4 * i + 3]);
                worstAlpha = std::max(worstAlpha, da);
                alphaOff += da > 1e-5;
                // Colour: same intersector, shading and clamp, same order; differences are float noise
                // of the hit point on a different (collinear) piece, amplified by the specular power
                // (measured worst 4.4e-5). 2e-4 still catches a hit on the wrong surface (a joint cap
                // inside the tube instead of the tangent cone: 2e-3..7e-3 on the tapered tube).
                for (int c = 0; c < 3; ++c) {
                    const double dc = std::abs(double(ref.rgba[4 * i + c]) - vrc.rgba[4 * i + c]);
                    worstColor = std::max(worstColor, dc);
                    if (dc > 2e-4 && colorOff++ < 4)
                        std::printf("  (%d,%d) c%d peel %.5f vrc %.5f alpha %.3f\n", x, y, c, ref.rgba[4 * i + c],
                                    vrc.rgba[4 * i + c], ref.rgba[4 * i + 3]);
                }
            }
        std::printf(
            "vrc transparent vs depth peeling: %zu px compared (%zu with 2+ tubes), worst alpha %.3g, worst "
            "colour %.3g\n",
            compared, multi, worstAlpha, worstColor);
        EXPECT_GT(multi, 20u);
        EXPECT_EQ(alphaOff, 0u) << "worst " << worstAlpha;
        EXPECT_EQ(colorOff, 0u) << "worst " << worstColor;
    }
}

HaloSpec haloSpec(float width, float depth, glm::vec3 color) {
    HaloSpec halo;
    halo.enabled = true;
    halo.width = width;
    halo.depth = depth;
    halo.color = color;
    return halo;
}

// style.halo on the straight tubes: rings of 0.6 radii (within one voxel of resolution 24, as the
// tubes), against depth peeling with the same rings, off the colour edges of the depth-peeled
// image (where a ray more or less through a rim is float noise). Measured: 207 of ~49,000
// compared pixels differ by more than 2e-3 (the tubes alone: 0, the test above).
TEST_F(GlTest, vrc_halos_match_depth_peeling_with_halos_off_edges) {
    const int w = 320, h = 240;
    const StyledLines lines = straightTubes(0.7f);
    const Camera cam = obliqueCamera();
    const HaloSpec halo = haloSpec(0.6f, 8.0f, glm::vec3(1.0f));
    const FrameImages ref = depthPeeled(lines, cam, w, h, halo);
    Scene vrcHalo = comparedVrcScene(w, h, true, 0, false);
    vrcHalo.style.halo = halo;
    const FrameImages vrc = render(vrcHalo, lines, cam);
    const FrameImages plain = render(comparedVrcScene(w, h, true, 0, false), lines, cam);
    auto colour = [&](int x, int y) {
        const std::size_t i = 4 * (std::size_t(y) * w + x);
        return glm::ivec4(
            glm::round(glm::vec4(ref.rgba[i], ref.rgba[i + 1], ref.rgba[i + 2], ref.rgba[i + 3]) * 32.0f));
    };
    std::size_t compared = 0, off = 0, rings = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            float d = 0, fromPlain = 0;
            for (int c = 0; c < 4; ++c) {
                d = std::max(d, std::abs(ref.rgba[4 * i + c] - vrc.rgba[4 * i + c]));
                fromPlain = std::max(fromPlain, std::abs(plain.rgba[4 * i + c] - vrc.rgba[4 * i + c]));
            }
            rings += fromPlain > 0.1f;
            if (onEdge(w, h, x, y, colour)) continue;
            ++compared;
            off += d > 2e-3f;
        }
    std::printf("vrc halos vs depth peeling: %zu px compared, %zu off by > 2e-3, %zu px changed by the rings\n",
                compared, off, rings);
    EXPECT_GT(rings, 300u);
    EXPECT_GT(compared, std::size_t(w * h) / 2);
    EXPECT_LE(off, compared / 100);
}

// A ring is found in the voxel of its entry and composited in the voxel of its depth (carried
// along the ray), so it falls in line with the hits of the voxels between, as in depth peeling.
// A front line (z = 0.5) crosses over a back line (z = 0), both of radius 0.08, with a ring of one
// radius pushed back 12 radii at its outer edge: where the ring passes over the back line, its
// depth lies in front of the back tube's surface for u < 0.44 and behind it beyond, so the back
// line is hidden by the inner part of the ring and shows through the outer part. The ring's entry
// lies ~3 voxels (resolution 10) in front of the back tube: composited where it is found, the
// ring would hide the back line everywhere.
TEST_F(GlTest, vrc_halo_rings_composite_at_their_depth_across_voxels) {
    const int w = 128, h = 128;
    std::vector<TestPolyline> p(2);
    for (int k = 0; k <= 4; ++k) {
        const float t = float(k) / 4.0f;
        p[0].push_back({{-1.0f + 2.0f * t, 0.0f, 0.5f}, 0.08f, glm::vec4(0.9f, 0.2f, 0.1f, 1.0f)});
        p[1].push_back({{0.0f, -1.0f + 2.0f * t, 0.0f}, 0.08f, glm::vec4(0.1f, 0.3f, 0.9f, 1.0f)});
    }
    const StyledLines lines = makeStyledLines(p);
    Camera cam;
    cam.eye = {0.0f, 0.0f, 3.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 40.0f;
    const HaloSpec halo = haloSpec(1.0f, 12.0f, glm::vec3(0.0f, 1.0f, 0.0f));
    const FrameImages ref = depthPeeled(lines, cam, w, h, halo);
    Scene ringed = vrcScene(w, h, 10, Transparency::DepthPeeling);
    ringed.render.vrc.quantization = 0;
    ringed.style.halo = halo;
    const FrameImages vrc = render(ringed, lines, cam);
    auto colour = [&](int x, int y) {
        const std::size_t i = 4 * (std::size_t(y) * w + x);
        return glm::ivec4(
            glm::round(glm::vec4(ref.rgba[i], ref.rgba[i + 1], ref.rgba[i + 2], ref.rgba[i + 3]) * 32.0f));
    };
    auto ringGreen = [&](int x, int y) {
        const std::size_t i = 4 * (std::size_t(y) * w + x);
        return ref.rgba[i + 1] > ref.rgba[i + 2];
    };
    std::size_t compared = 0, off = 0, showThrough = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            // The back line's blue where the front line's ring lies over it (|y| in (0.08, 0.16)
            // around the front line's axis; the back line is at |x| < 0.08).
            const Ray ray = pixelRay(cam, w, h, float(x), float(y));
            const glm::vec3 atFront = ray.origin + ((0.5f - ray.origin.z) / ray.dir.z) * ray.dir;
            const bool inRing = std::abs(atFront.y) > 0.08f && std::abs(atFront.y) < 0.16f;
            const bool ringOverBack = inRing && std::abs(atFront.x) < 0.05f;
            showThrough += ringOverBack && ref.rgba[4 * i + 2] > ref.rgba[4 * i + 1];
            if (ringOverBack) {
                // The ring's green or the back tube's blue (off the border between the two, where a
                // ray more or less is float noise): the same in both.
                if (onEdge(w, h, x, y, ringGreen)) continue;
                ++compared;
                off += (vrc.rgba[4 * i + 1] > vrc.rgba[4 * i + 2]) != ringGreen(x, y);
                continue;
            }
            if (onEdge(w, h, x, y, colour)) continue;
            float d = 0;
            for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(ref.rgba[4 * i + c] - vrc.rgba[4 * i + c]));
            ++compared;
            off += d > 0.05f;
        }
    std::printf(
        "vrc halo rings across voxels: %zu px compared, %zu differ from depth peeling, %zu show the back line "
        "through a ring\n",
        compared, off, showThrough);
    EXPECT_GT(showThrough, 6u);  // not vacuous: depth peeling shows the back line through the ring
    EXPECT_EQ(off, 0u);
}

// A stack of tubes along the view direction, axes at y = 0 (orthographic rays parallel to z): on
// the rays well inside the tubes' silhouette (|y| <= 0.6 r) the depth-peeled alpha is `alpha` and
// the ray caster's image equals depth peeling's up to float noise of the hit points (alpha 1e-5,
// colour 2e-4, as the straight-tube test); more than 4 rows of such rays, or the test is vacuous.
void expectStackMatches(const FrameImages& ref, const FrameImages& vrc, const Camera& cam, int w, int h, float r,
                        double alpha, const char* what) {
    ASSERT_EQ(vrc.rgba.size(), ref.rgba.size());
    std::size_t stackPixels = 0, alphaOff = 0, colorOff = 0;
    double worstAlpha = 0, worstColor = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const Ray ray = pixelRay(cam, w, h, float(x), float(y));
            if (std::abs(ray.origin.y) > 0.6f * r) continue;
            ++stackPixels;
            EXPECT_NEAR(ref.rgba[4 * i + 3], alpha, 1e-5) << x << "," << y;
            const double da = std::abs(double(ref.rgba[4 * i + 3]) - vrc.rgba[4 * i + 3]);
            worstAlpha = std::max(worstAlpha, da);
            alphaOff += da > 1e-5;
            for (int c = 0; c < 3; ++c) {
                const double dc = std::abs(double(ref.rgba[4 * i + c]) - vrc.rgba[4 * i + c]);
                worstColor = std::max(worstColor, dc);
                colorOff += dc > 2e-4;
            }
        }
    std::printf("vrc %s vs depth peeling: %zu px, worst alpha %.3g, worst colour %.3g\n", what, stackPixels, worstAlpha,
                worstColor);
    EXPECT_GT(stackPixels, std::size_t(4 * w));
    EXPECT_EQ(alphaOff, 0u) << "worst " << worstAlpha;
    EXPECT_EQ(colorOff, 0u) << "worst " << worstColor;
}

// Kanzler et al. 2019, Sec. 4: every intersection in a voxel is composited in order. A stack of
// 20 parallel tubes one behind the other along the view direction, all in the voxels of one
// column (resolution 3: voxels ~1 wide, the stack 0.64 deep, so at least 10 tubes share a voxel
// on every ray through the stack): more hits per voxel than the ray caster's 8 hit slots.
// Transparent VRC must blend all 20, as depth peeling does (alpha 1 - 0.8^20 = 0.988 on the
// stack; 8 per voxel would give 1 - 0.8^16 = 0.972 at best).
TEST_F(GlTest, vrc_transparent_blends_every_hit_of_a_voxel_crossed_by_more_tubes_than_hit_slots) {
    const int w = 48, h = 40, tubes = 20;
    const float r = 0.015f, spacing = 0.032f, a = 0.2f;
    std::vector<TestPolyline> stack;
    for (int k = 0; k < tubes; ++k) {
        const float z = (float(k) - 0.5f * float(tubes - 1)) * spacing;
        // A different colour per tube: the order of compositing shows in the colour.
        const glm::vec4 color(0.1f + 0.8f * float(k) / float(tubes - 1), 0.9f - 0.8f * float(k % 5) / 4.0f,
                              0.2f + 0.6f * float(k % 3) / 2.0f, a);
        stack.push_back({{{-1.0f, 0.0f, z}, r, color}, {{1.0f, 0.0f, z}, r, color}});
    }
    const StyledLines lines = makeStyledLines(stack);
    Camera cam;
    cam.eye = {0.013f, 0.0f, 3.0f};
    cam.target = {0.013f, 0.0f, 0.0f};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 0.1f;  // 2.5 mm pixels: 12 rows across the stack

    VrcBuildOptions o;
    o.resolution = 3;
    o.quantization = 0;
    const VrcModel model = buildVrcModel(lines, o);
    std::uint32_t mostPieces = 0;
    for (const VrcVoxel& v : model.voxels) mostPieces = std::max(mostPieces, v.count & kCountMask);
    ASSERT_GE(mostPieces, 10u) << "the premise: a voxel holds more tubes than the 8 hit slots";

    const FrameImages ref = depthPeeled(lines, cam, w, h);
    for (bool neighbors : {true, false}) {
        {
            // Exact ends: snapped to bins of ~1/32 voxel, tubes 0.03 voxel wide would move off the rows.
            SCOPED_TRACE(neighbors ? "neighbors on" : "neighbors off (copies)");
            Scene scene = comparedVrcScene(w, h, true, 0, neighbors);
            scene.render.vrc.resolution = 3;
            const FrameImages vrc = render(scene, lines, cam);
            expectStackMatches(ref, vrc, cam, w, h, r, 1.0 - std::pow(1.0 - a, tubes), "stacked tubes");
        }
    }
}

// A polyline is blended once per voxel, at its nearest entry (Kanzler et al. 2019, Sec. 4.1: an
// intersection of the same line is considered only once), also when its hits fall into different
// batches of a voxel with more hits than hit slots. The stack of the test above with the first
// tube's polyline bent back at x = 1 into the place of the last tube of the same voxel (the nearer
// ten tubes fill one voxel, the farther ten the next): along the middle rays its second leg is the
// tenth hit of its voxel, in the second batch, and is skipped. The image is depth peeling of the
// stack without that leg (a straight tube in the first leg's place, 19 tubes).
TEST_F(GlTest, vrc_transparent_blends_a_polyline_once_per_voxel_across_hit_batches) {
    const int w = 48, h = 40, tubes = 20;
    const float r = 0.015f, spacing = 0.032f, a = 0.2f;
    auto zOf = [&](int k) { return (float(k) - 0.5f * float(tubes - 1)) * spacing; };
    auto colorOf = [&](int k) {
        return glm::vec4(0.1f + 0.8f * float(k) / float(tubes - 1), 0.9f - 0.8f * float(k % 5) / 4.0f,
                         0.2f + 0.6f * float(k % 3) / 2.0f, a);
    };
    // Tubes 0..9 have z < 0 (the farther voxel from a camera on +z), 10..19 z > 0.
    std::vector<TestPolyline> bent, reference;
    for (int k = 1; k < tubes; ++k) {
        if (k == 9) {
            bent.push_back({{{-1.0f, 0.0f, zOf(9)}, r, colorOf(9)},
                            {{1.0f, 0.0f, zOf(9)}, r, colorOf(9)},
                            {{1.0f, 0.0f, zOf(0)}, r, colorOf(9)},
                            {{-1.0f, 0.0f, zOf(0)}, r, colorOf(9)}});
        } else {
            bent.push_back({{{-1.0f, 0.0f, zOf(k)}, r, colorOf(k)}, {{1.0f, 0.0f, zOf(k)}, r, colorOf(k)}});
        }
        reference.push_back({{{-1.0f, 0.0f, zOf(k)}, r, colorOf(k)}, {{1.0f, 0.0f, zOf(k)}, r, colorOf(k)}});
    }
    const StyledLines bentLines = makeStyledLines(bent), referenceLines = makeStyledLines(reference);
    Camera cam;
    cam.eye = {0.013f, 0.0f, 3.0f};
    cam.target = {0.013f, 0.0f, 0.0f};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 0.1f;

    VrcBuildOptions o;
    o.resolution = 3;
    o.quantization = 0;
    const VrcModel model = buildVrcModel(bentLines, o);
    const glm::ivec3 front =
        glm::ivec3(glm::floor((glm::vec3(0.013f, 0.0f, zOf(10)) - model.origin) / model.voxelSize));
    const glm::ivec3 back = glm::ivec3(glm::floor((glm::vec3(0.013f, 0.0f, zOf(9)) - model.origin) / model.voxelSize));
    ASSERT_EQ(front - back, glm::ivec3(0, 0, 1)) << "the premise: ten tubes in each of two voxels along the rays";
    ASSERT_EQ(back.z, int(std::floor((zOf(0) - model.origin.z) / model.voxelSize)));

    const FrameImages ref = depthPeeled(referenceLines, cam, w, h);
    for (bool neighbors : {true, false}) {
        SCOPED_TRACE(neighbors ? "neighbors on" : "neighbors off (copies)");
        Scene scene = comparedVrcScene(w, h, true, 0, neighbors);
        scene.render.vrc.resolution = 3;
        const FrameImages vrc = render(scene, bentLines, cam);
        expectStackMatches(ref, vrc, cam, w, h, r, 1.0 - std::pow(1.0 - a, tubes - 1), "bent polyline across batches");
    }
}

// render.vrc.path_length_opacity: a straight horizontal tube seen side-on with an orthographic
// camera. Every pixel ray crosses the axis at right angles, so its chord through the tube is
// 2 sqrt(r^2 - d^2) at the ray's distance d from the axis, and its alpha is
// 1 - (1 - a)^(chord / 2r): a on the axis row, falling to 0 at the silhouette. A wrong exit distance
// (e.g. the entry's, or a fixed 2r) breaks the profile away from the axis (at d = 0.7 r the
// expected 0.395 against a = 0.5). The tube's pieces end at voxel faces (resolution 12: ~0.18 >
// r, the exact case of the straight-tube tests above); columns on those faces are included.
TEST_F(GlTest, vrc_path_length_opacity_follows_the_chord_through_a_tube_seen_side_on) {
    const int w = 33, h = 65;  // odd height: the middle row's ray passes through the axis
    const float r = 0.08f, a = 0.5f;
    TestPolyline tube;
    tube.push_back({{-1.0f, 0.0f, 0.0f}, r, {0.8f, 0.4f, 0.2f, a}});
    tube.push_back({{1.0f, 0.0f, 0.0f}, r, {0.8f, 0.4f, 0.2f, a}});
    const StyledLines lines = makeStyledLines({tube});
    Camera cam;
    cam.eye = {0.013f, 0.0f, 3.0f};  // off x = 0: no column on the middle voxel face
    cam.target = {0.013f, 0.0f, 0.0f};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 0.26f;  // 4 mm pixels: 40 pixels across the tube
    const float pixel = cam.orthoHeight / float(h);
    for (bool neighbors : {true, false}) {
        SCOPED_TRACE(neighbors ? "neighbors on" : "neighbors off (copies)");
        Scene scene = comparedVrcScene(w, h, true, 0, neighbors);
        scene.render.vrc.resolution = 12;
        const FrameImages styleAlpha = render(scene, lines, cam);
        scene.render.vrc.pathLengthOpacity = true;
        const std::unique_ptr<tc::Technique> t = gl::createTechnique(scene, lines);
        EXPECT_EQ(t->describe().value("path_length_opacity", false), true);
        const FrameImages pathAlpha = render(*t, scene, cam);
        ASSERT_EQ(pathAlpha.rgba.size(), styleAlpha.rgba.size());
        std::size_t covered = 0, checked = 0, offProfile = 0, offStyle = 0, offColour = 0;
        double worst = 0, centre = -1;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                const Ray ray = pixelRay(cam, w, h, float(x), float(y));
                // The axis is the x axis and the rays are parallel to z.
                const double d = std::abs(double(ray.origin.y));
                const float on = pathAlpha.rgba[4 * i + 3], off = styleAlpha.rgba[4 * i + 3];
                // A ray tangent to the tube (row 52: d = r = 20 pixels, to float error) may meet it with a
                // chord of 0: path-length alpha 0 against the style's a. Everywhere else they agree.
                if (std::abs(d - double(r)) > 1e-6) {
                    EXPECT_EQ(on > 0.0f, off > 0.0f) << "coverage differs at " << x << "," << y;
                }
                if (d < r - 0.5 * pixel) {
                    EXPECT_GT(off, 0.0f) << x << "," << y;
                }
                if (off <= 0.0f) continue;
                ++covered;
                offStyle += std::abs(off - a) > 1e-6f;  // key false: every covered pixel has the style alpha
                // Premultiplied colour: the same shaded colour, scaled by the alpha it was blended with.
                for (int c = 0; c < 3; ++c)
                    offColour += std::abs(pathAlpha.rgba[4 * i + c] - styleAlpha.rgba[4 * i + c] * (on / off)) > 1e-5f;
                EXPECT_LE(on, a + 1e-6f) << x << "," << y;
                // Pixel-edge margin: half a pixel from the silhouette the chord's slope in d is
                // unbounded and the intersector's float error is magnified; those rims are only bounded.
                if (d > r - 0.5 * pixel) continue;
                const double chord = 2.0 * std::sqrt(double(r) * r - d * d);
                const double expected = 1.0 - std::pow(1.0 - a, chord / (2.0 * r));
                const double err = std::abs(on - expected);
                worst = std::max(worst, err);
                // Float noise of the intersector's t is ~1e-6 of alpha (measured worst 7.5e-7); a chord
                // 1 % off moves alpha by ~3e-3 at d = 0.7 r.
                offProfile += err > 1e-4;
                ++checked;
                if (y == h / 2 && x == w / 2) centre = on;
            }
        std::printf(
            "vrc path-length opacity: %zu px covered, %zu on the profile, worst |alpha - analytic| %.3g, "
            "centre alpha %.6f\n",
            covered, checked, worst, centre);
        EXPECT_GT(checked, std::size_t(w * 36));  // ~39 rows of the tube's 40
        EXPECT_EQ(offProfile, 0u) << "worst " << worst;
        EXPECT_NEAR(centre, a, 1e-5);
        EXPECT_EQ(offStyle, 0u);
        EXPECT_EQ(offColour, 0u);
    }
}

TEST_F(GlTest, vrc_quantized_model_renders_close_to_exact_and_early_termination_only_drops_light) {
    const int w = 96, h = 72;
    const StyledLines lines = straightTubes(0.5f);
    const Camera cam = obliqueCamera();
    const FrameImages exact = render(comparedVrcScene(w, h, true, 0, true), lines, cam);
    Scene qs = comparedVrcScene(w, h, true, 32, true);
    const FrameImages quant = render(qs, lines, cam);
    qs.render.vrc.opacityThreshold = 0.4f;
    const FrameImages early = render(qs, lines, cam);
    double sumDiff = 0;
    std::size_t lessAlpha = 0, moreAlpha = 0;
    for (std::size_t i = 0; i < exact.id.size(); ++i) {
        sumDiff += std::abs(exact.rgba[4 * i + 3] - quant.rgba[4 * i + 3]);
        // Early termination stops at alpha >= 0.4: what it blends is a prefix of the full sum.
        lessAlpha += early.rgba[4 * i + 3] < quant.rgba[4 * i + 3] - 1e-6f;
        moreAlpha += early.rgba[4 * i + 3] > quant.rgba[4 * i + 3] + 1e-6f;
        if (early.rgba[4 * i + 3] < quant.rgba[4 * i + 3] - 1e-6f) {
            EXPECT_GE(early.rgba[4 * i + 3], 0.4f - 1e-6f);
        }
    }
    // Snapping ends by <= 1/64 voxel moves silhouettes by a fraction of a pixel: mean alpha error
    // stays small (measured ~1e-3).
    EXPECT_LT(sumDiff / double(exact.id.size()), 0.01);
    EXPECT_GT(lessAlpha, 0u);  // pixels with two tubes in different voxels (0.75) stop after one (0.5)
    EXPECT_EQ(moreAlpha, 0u);
}

// Summed red channel, over the middle rows, of the pixels within 0.06 (a tube radius) of world x
// = xWorld in an orthographic view along -z centred on x = 0 (the shadow tests' vertical tubes).
float redOfTubeAt(const FrameImages& f, float orthoHeight, float xWorld) {
    const int w = f.width, h = f.height;
    float sum = 0;
    for (int y = h / 4; y < 3 * h / 4; ++y)
        for (int x = 0; x < w; ++x) {
            const float px = (float(x) + 0.5f - 0.5f * float(w)) / float(h) * orthoHeight;
            if (std::abs(px - xWorld) <= 0.06f) sum += f.rgba[4 * (std::size_t(y) * std::size_t(w) + std::size_t(x))];
        }
    return sum;
}

// The shadow tests' scene: two grey tubes of radius 0.06 along y at x = -0.15 and 0.15, z = 0.
StyledLines twoGreyTubes() {
    const glm::vec4 grey(0.7f, 0.7f, 0.7f, 1.0f);
    return makeStyledLines({{{{-0.15f, -0.8f, 0.0f}, 0.06f, grey}, {{-0.15f, 0.8f, 0.0f}, 0.06f, grey}},
                            {{{0.15f, -0.8f, 0.0f}, 0.06f, grey}, {{0.15f, 0.8f, 0.0f}, 0.06f, grey}}});
}

TEST_F(GlTest, vrc_soft_shadows_darken_the_tube_behind_another_toward_the_light_only) {
    // Two parallel tubes side by side seen from +z, the light from +x (camera right): the left tube
    // lies in the right one's shadow; the right one has nothing toward the light.
    const int w = 96, h = 64;
    const StyledLines lines = twoGreyTubes();
    const Camera cam = orthographic({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 1.0f);
    Scene scene = comparedVrcScene(w, h, false, 32, true);
    scene.lighting.direction = {1.0f, 0.0f,
                                0.0f};  // horizontal: cones from the visible upper halves cross the other tube
    scene.render.ao.resolution = 48;
    scene.render.ao.distance = 0.5f;
    const FrameImages lit = render(scene, lines, cam);
    scene.render.vrc.shadows = true;
    scene.render.vrc.shadowApertureDeg = 10;
    const FrameImages shadowed = render(scene, lines, cam);
    auto brightest = [&](const FrameImages& f, float xWorld) { return redOfTubeAt(f, cam.orthoHeight, xWorld); };
    const float leftLit = brightest(lit, -0.15f), leftShadowed = brightest(shadowed, -0.15f);
    const float rightLit = brightest(lit, 0.15f), rightShadowed = brightest(shadowed, 0.15f);
    std::printf("vrc soft shadows: left tube %.4f -> %.4f, right tube %.4f -> %.4f\n", leftLit, leftShadowed, rightLit,
                rightShadowed);
    ASSERT_GT(leftLit, 10.0f);
    // In the other tube's shadow (measured -10 % of the summed red channel: ambient is not
    // shadowed, and the occluder is a 48^3 density of a tube 3 voxels wide, so a 10-degree cone
    // reads it partly, at trilinear falloff). 5 % is far above float noise (the right tube is
    // bit-identical) and below the effect.
    EXPECT_LT(leftShadowed, 0.95f * leftLit);
    EXPECT_GT(rightShadowed, 0.99f * rightLit);  // its own tube does not shadow it (measured: equal)
}

TEST_F(GlTest, vrc_hard_shadows_from_representative_lines_darken_the_tube_behind_another) {
    // As the soft shadow test: the left tube lies in the right one's shadow for a light from +x.
    // Hard shadows trace a ray per shaded point against the level-1 representative lines (straight
    // tubes: their representatives are the tubes' axes), so the shadowed pixels lose all diffuse
    // and specular light; the right tube has nothing toward the light.
    const int w = 96, h = 64;
    const StyledLines lines = twoGreyTubes();
    const Camera cam = orthographic({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 1.0f);
    Scene scene = comparedVrcScene(w, h, false, 32, false);
    scene.lighting.direction = {1.0f, 0.0f, 0.0f};
    const FrameImages lit = render(scene, lines, cam);
    scene.render.vrc.shadows = true;
    scene.render.vrc.shadowMode = VrcSpec::ShadowMode::Hard;
    scene.render.vrc.shadowLevel = 1;
    const FrameImages shadowed = render(scene, lines, cam);
    auto sum = [&](const FrameImages& f, float xWorld) { return redOfTubeAt(f, cam.orthoHeight, xWorld); };
    const float leftLit = sum(lit, -0.15f), leftShadowed = sum(shadowed, -0.15f);
    const float rightLit = sum(lit, 0.15f), rightShadowed = sum(shadowed, 0.15f);
    std::printf("vrc hard shadows: left tube %.4f -> %.4f, right tube %.4f -> %.4f\n", leftLit, leftShadowed, rightLit,
                rightShadowed);
    ASSERT_GT(leftLit, 10.0f);
    // The lit side of the left tube faces the right tube: most of its diffuse light goes (ambient
    // stays). 20 % is far from float noise and below the effect.
    EXPECT_LT(leftShadowed, 0.8f * leftLit);
    EXPECT_GT(rightShadowed, 0.999f * rightLit);  // nothing toward the light, no self-shadowing
}

TEST_F(GlTest, vrc_piece_array_split_over_several_storage_blocks_renders_the_single_block_image) {
    // The exact piece array of a large model is split over several shader storage blocks (one
    // block is capped at GL_MAX_SHADER_STORAGE_BLOCK_SIZE). A tiny forced block size splits this
    // small model the same way: the image, depth and ids must be bit-identical to one block,
    // transparent (every piece along the ray is read) and opaque. Quantized pieces are read
    // through one texture buffer whatever the block size: no blocks, the same image.
    const int w = 96, h = 72;
    const StyledLines lines = straightTubes(0.4f);
    const Camera cam = obliqueCamera();
    for (int q : {32, 0}) {
        for (bool transparent : {true, false}) {
            SCOPED_TRACE("q=" + std::to_string(q) + (transparent ? " transparent" : " opaque"));
            VrcBuildOptions o;
            o.resolution = 24;
            o.quantization = q;
            o.lod = false;
            o.dilate = true;
            const VrcModel model = buildVrcModel(lines, o);
            const Scene scene = comparedVrcScene(w, h, transparent, q, false);
            const std::unique_ptr<gl::VrcRenderer> one = gl::VrcRenderer::create(scene, lines, model);
            // The smallest power-of-two block that fits the model in kMaxPieceBlocks blocks: 5..8
            // blocks, the last one partly filled.
            const std::size_t perBlock = std::size_t(1) << int(std::ceil(
                                             std::log2(double(model.pieceCount()) / gl::VrcRenderer::kMaxPieceBlocks)));
            ASSERT_GE(perBlock, 16u);
            const std::unique_ptr<gl::VrcRenderer> split =
                gl::VrcRenderer::create(scene, lines, model, perBlock * model.bytesPerPiece());
            const bool texture = q > 0;
            const std::size_t blocks = (model.pieceCount() + perBlock - 1) / perBlock;
            EXPECT_GE(blocks, 5u);
            EXPECT_EQ(one->describe()["piece_blocks"], texture ? 0u : 1u);
            EXPECT_EQ(split->describe()["piece_blocks"], texture ? 0u : blocks);
            EXPECT_EQ(split->describe()["piece_texture"], texture);
            const FrameImages a = render(*one, scene, cam), b = render(*split, scene, cam);
            std::size_t covered = 0;
            for (std::size_t i = 0; i < a.id.size(); ++i) covered += a.id[i] != kBackgroundId;
            EXPECT_GT(covered, std::size_t(w * h / 10));
            EXPECT_EQ(a.rgba, b.rgba);
            EXPECT_EQ(a.id, b.id);
            EXPECT_EQ(std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)), 0);
        }
    }
}

TEST_F(GlTest, vrc_exact_model_needing_more_storage_blocks_than_bindings_is_an_input_error) {
    // Exact pieces are read from storage blocks only; the quantized model of the same lines, read
    // through one texture buffer, renders at the same forced block size.
    const StyledLines lines = straightTubes(0.4f);
    for (int q : {0, 32}) {
        SCOPED_TRACE("q=" + std::to_string(q));
        VrcBuildOptions o;
        o.resolution = 24;
        o.quantization = q;
        o.dilate = true;
        const VrcModel model = buildVrcModel(lines, o);
        const Scene scene = comparedVrcScene(32, 24, true, o.quantization, false);
        const std::size_t perBlock = 16;
        ASSERT_GT(model.pieceCount(), perBlock * gl::VrcRenderer::kMaxPieceBlocks);
        if (q == 0) {
            EXPECT_THROW(gl::VrcRenderer::create(scene, lines, model, perBlock * model.bytesPerPiece()), InputError);
        } else {
            const std::unique_ptr<gl::VrcRenderer> r =
                gl::VrcRenderer::create(scene, lines, model, perBlock * model.bytesPerPiece());
            EXPECT_EQ(r->describe()["piece_texture"], true);
            EXPECT_EQ(r->describe()["piece_blocks"], 0u);
        }
    }
}

TEST(VrcPieceStorage, quantized_pieces_read_through_one_texture_up_to_its_texels_exact_ones_from_at_most_8_blocks) {
    // llvmpipe's limits: 128 MiB per storage block, 128 Mi texels per texture buffer.
    const std::size_t blockBytes = std::size_t(128) << 20, texels = std::size_t(128) << 20;
    // A model with copies past 8 blocks of 16-byte pieces (64 Mi of them), within the texels: read
    // through the texture, so the copies stay (create() falls back to neighbour tests otherwise).
    const gl::VrcRenderer::PieceStorage quantized =
        gl::VrcRenderer::pieceStorage(83'000'000, 16, true, blockBytes, texels);
    EXPECT_TRUE(quantized.texture);
    EXPECT_EQ(quantized.blocks, 0u);
    EXPECT_TRUE(quantized.fits());
    // Exact pieces (64 bytes): 2 Mi per block, 40 blocks.
    const gl::VrcRenderer::PieceStorage exact =
        gl::VrcRenderer::pieceStorage(83'000'000, 64, false, blockBytes, texels);
    EXPECT_FALSE(exact.texture);
    EXPECT_EQ(exact.perBlock, std::size_t(2) << 20);
    EXPECT_EQ(exact.blocks, 40u);
    EXPECT_FALSE(exact.fits());
    // Exactly 8 full blocks fit; one piece more does not.
    EXPECT_TRUE(gl::VrcRenderer::pieceStorage(std::size_t(16) << 20, 64, false, blockBytes, texels).fits());
    EXPECT_FALSE(gl::VrcRenderer::pieceStorage((std::size_t(16) << 20) + 1, 64, false, blockBytes, texels).fits());
    // Quantized pieces past the texels go to blocks: 8 Mi per block, 17 of them.
    const gl::VrcRenderer::PieceStorage past = gl::VrcRenderer::pieceStorage(texels + 1, 16, true, blockBytes, texels);
    EXPECT_FALSE(past.texture);
    EXPECT_EQ(past.blocks, 17u);
    EXPECT_FALSE(past.fits());
    // An empty model binds one piece.
    EXPECT_EQ(gl::VrcRenderer::pieceStorage(0, 64, false, blockBytes, texels).blocks, 1u);
}

TEST_F(GlTest, vrc_gpu_build_produces_the_cpu_model_bit_for_bit) {
    RandomSceneOptions o;
    o.polylines = 40;
    o.minSegments = 5;
    o.maxSegments = 30;
    o.radiusMin = 0.005f;
    o.stepMin = 0.02f;
    o.stepMax = 0.2f;
    for (const StyledLines& lines : {randomLineScene(5, o), straightTubes(0.5f)}) {
        for (int q : {32, 7, 0}) {
            VrcBuildOptions b;
            b.resolution = 20;
            b.quantization = q;
            b.lod = false;
            b.dilate = q == 7;  // copies: added to both by the same CPU function (one case suffices)
            const VrcModel cpu = buildVrcModel(lines, b);
            const VrcModel gpu = gl::buildVrcModelGpu(lines, b);
            ASSERT_EQ(gpu.pieceCount(), cpu.pieceCount()) << "q=" << q;
            ASSERT_GT(cpu.pieceCount(), 100u);
            if (b.dilate) {
                EXPECT_GT(cpu.copies, 0u);
            }
            EXPECT_EQ(gpu.copies, cpu.copies);
            EXPECT_EQ(gpu.size, cpu.size);
            EXPECT_EQ(gpu.pieceVoxel, cpu.pieceVoxel) << "q=" << q;
            std::size_t headerDiffs = 0, pieceDiffs = 0;
            for (std::size_t v = 0; v < cpu.voxels.size(); ++v)
                headerDiffs +=
                    gpu.voxels[v].offset != cpu.voxels[v].offset || gpu.voxels[v].count != cpu.voxels[v].count;
            for (std::size_t i = 0; i < cpu.pieceCount(); ++i) {
                const bool same = q > 0 ? std::memcmp(&gpu.compact[i], &cpu.compact[i], sizeof(VrcCompactPiece)) == 0
                                        : std::memcmp(&gpu.exact[i], &cpu.exact[i], sizeof(VrcExactPiece)) == 0;
                if (!same && pieceDiffs++ < 3) {
                    const VrcPiece a = cpu.piece(i), g = gpu.piece(i);
                    ADD_FAILURE() << "q=" << q << " piece " << i << ": cpu a (" << a.a.x << "," << a.a.y << "," << a.a.z
                                  << ") r " << a.ra << " gpu a (" << g.a.x << "," << g.a.y << "," << g.a.z << ") r "
                                  << g.ra;
                }
            }
            EXPECT_EQ(headerDiffs, 0u) << "q=" << q;
            EXPECT_EQ(pieceDiffs, 0u) << "q=" << q;
        }
    }
}

}  // namespace
}  // namespace tc::test
