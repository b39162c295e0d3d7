// The opaque rounded-cone technique (G-buffer ray casting + deferred shading) against its CPU twin,
// tc::renderReferenceOpaque, pixel by pixel: coverage, view depth, world normal, polyline id and
// shaded colour, on small random scenes and on the views where ray casting on billboards tends to
// break (eye inside a tube or a cap, view along the axis, a tube through the eye plane, extreme
// radius ratios, sub-pixel tubes).
//
// Both sides cast the same pixel-centre rays (core/camera.h, shaders/camera.glsl) through the same
// intersector (core/rounded_cone.h, shaders/rounded_cone.glsl), so the differences measured here
// are float evaluation order on llvmpipe, not method. The tolerances below are set from that.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/cpu_reference.h"
#include "core/rounded_cone.h"
#include "core/scene.h"
#include "core/technique.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

// View depth: |gpu - cpu| <= 1e-5 * max(depth, distance from the eye to the scene's centre).
// Both sides solve the same quadratics in the same frame (origin at the ray point closest to the
// segment), so the hit parameter t = t0 + t_local carries a few float ulps (~1e-7 each) of t0,
// the distance to the segment, not of the depth: a tube passing beside the eye (depth ~0.004)
// still has t0 ~ 1. 1e-5 leaves ~100 ulps for llvmpipe's contracted multiply-adds and reordered
// dot products and still catches a wrong root, a wrong surface or a depth measured along the
// wrong direction (all >= 1e-3 here). Measured worst: 7.8e-6 (tube through the eye plane).
constexpr double kDepthRelTolerance = 1e-5;
// Grazing pixels: the visible segment's chord tOut - tIn is below kGrazingChord x its smaller
// diameter, i.e. the ray passes within 0.13 % of the radius of the silhouette. There the root is
// ill-conditioned (dt/dray ~ diameter / chord >= 10, up to sqrt(r * eps) when the chord -> 0): the
// float CPU reference itself is 2.5e-5 off double precision on such a pixel. Depth is checked
// with a 1e-3 relative bound (a wrong surface is still >= 1e-2 off), the normal and colour
// (which follow the ill-conditioned hit point) are not; the count of such pixels is reported.
constexpr double kGrazingChord = 0.1;
constexpr double kGrazingDepthRelTolerance = 1e-3;
// Normal angle, radians, away from grazing pixels: normals are normalize(gradient) at the hit,
// ~1e-6 rad of float noise times the conditioning of the hit (<= 10 outside grazing pixels).
// 1e-3 rad is far below anything visible and far above that. Measured worst: 3.2e-4 (thin tubes).
constexpr double kNormalAngleTolerance = 1e-3;
// Shaded colour, absolute (linear, premultiplied, alpha 1): the G-buffer stores albedo as
// RGBA16F (11-bit mantissa: relative error <= 2^-11 ~ 4.9e-4 per channel), scaled by
// ambient + diffuse <= 1; the specular term depends only on the normal (above) and the light.
// 2e-3 is 4x the half-float bound. Measured worst: 4.9e-4, the half-float bound itself.
constexpr double kColorTolerance = 2e-3;
// Two segments whose visible depths are within this relative distance at a pixel are a depth tie:
// either may win on either side (the GPU compares depth / far in a 32-bit depth buffer, the CPU
// compares t), so id, normal and colour are not compared there if the two segments would store
// different values (another polyline id, normals more than half the tolerance apart, albedo more
// than a quarter of the colour tolerance apart). 1e-4 is 10x the depth tolerance.
constexpr double kTieRelDistance = 1e-4;

struct Hit {
    bool hit = false;
    float t = 0, depth = 0;
    glm::vec3 normal{0};
    glm::vec3 albedo{0};
    std::uint32_t id = kBackgroundId;
    bool grazing = false;  // chord < kGrazingChord * smaller diameter
};

// What segment `s` shows at `ray`: the same rule as renderReferenceOpaque (tIn if > 0, else tOut).
Hit visibleHit(const StyledLines& lines, std::size_t s, const Ray& ray, const Camera& cam) {
    const std::uint32_t v0 = lines.segmentVertices[2 * s], v1 = lines.segmentVertices[2 * s + 1];
    const glm::vec4 a = lines.positionRadius[v0], b = lines.positionRadius[v1];
    ConeInterval iv = intersectRoundedCone(ray, {glm::vec3(a), a.w, glm::vec3(b), b.w});
    Hit h;
    const auto nearest = nearestPositiveHit(iv);
    if (!nearest) return h;
    h.t = nearest->t, h.normal = nearest->normal;
    h.hit = true;
    h.grazing = iv.tOut - iv.tIn < kGrazingChord * 2.0 * std::min(a.w, b.w);
    h.depth = cam.projection == Projection::Orthographic ? h.t : h.t * glm::dot(ray.dir, cam.forward());
    const glm::vec3 p = ray.origin + h.t * ray.dir, ba = glm::vec3(b) - glm::vec3(a);
    const float m0 = glm::dot(ba, ba);
    const float u = m0 > 0.0f ? glm::clamp(glm::dot(p - glm::vec3(a), ba) / m0, 0.0f, 1.0f) : 0.0f;
    h.albedo = glm::mix(glm::vec3(lines.color[v0]), glm::vec3(lines.color[v1]), u);
    h.id = lines.polylineId[v0];
    return h;
}

double angleBetween(glm::vec3 a, glm::vec3 b) {
    // atan2(|a x b|, a.b) is accurate for tiny angles, unlike acos(a.b).
    glm::dvec3 da(a), db(b);
    return std::atan2(glm::length(glm::cross(da, db)), glm::dot(da, db));
}

enum PixelFlag : char {
    // Another segment is visible within kTieRelDistance of the nearest one and would store other
    // values in the G-buffer (id, normal or albedo).
    DepthTie = 1,
    // The nearest segment is hit at grazing incidence (kGrazingChord).
    Grazing = 2,
};

// PixelFlags per pixel, from the CPU intersector with the reference's visibility rule.
std::vector<char> classifyPixels(const StyledLines& lines, const Camera& cam, int w, int h) {
    std::vector<char> flags(std::size_t(w) * h, 0);
    const std::size_t segments = lines.segmentCount();
    std::vector<Hit> hits(segments);
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            const Ray ray = pixelRay(cam, w, h, float(px), float(py));
            std::size_t best = segments;
            for (std::size_t s = 0; s < segments; ++s) {
                hits[s] = visibleHit(lines, s, ray, cam);
                if (hits[s].hit && (best == segments || hits[s].t < hits[best].t)) best = s;
            }
            if (best == segments) continue;
            const Hit& b = hits[best];
            if (b.grazing) flags[std::size_t(py) * w + px] |= Grazing;
            for (std::size_t s = 0; s < segments; ++s) {
                if (s == best || !hits[s].hit || hits[s].t - b.t > kTieRelDistance * b.t) continue;
                const bool differs = hits[s].id != b.id ||
                                     angleBetween(hits[s].normal, b.normal) > 0.5 * kNormalAngleTolerance ||
                                     glm::length(hits[s].albedo - b.albedo) > 0.25 * kColorTolerance;
                if (differs) flags[std::size_t(py) * w + px] |= DepthTie;
            }
        }
    return flags;
}

struct Comparison {
    int width = 0, height = 0;
    std::size_t cpuHits = 0, gpuHits = 0;
    std::size_t silhouette = 0;          // CPU 3x3 neighbourhood mixes hit and background
    std::size_t coverageMismatch = 0;    // outside silhouettes: must be 0
    std::size_t silhouetteMismatch = 0;  // on silhouettes: reported
    std::size_t cpuHitGpuMiss = 0;       // anywhere, silhouettes included (billboard coverage)
    std::size_t compared = 0, ties = 0;  // both hit; of those, depth ties
    std::size_t grazing = 0;             // both hit, grazing incidence (not a tie)
    std::size_t depthOver = 0, normalOver = 0, idMismatch = 0, colorOver = 0;
    double maxDepthRel = 0, maxGrazingDepthRel = 0, maxNormalAngle = 0, maxColor = 0;
    std::string firstProblems;  // a few pixels that failed, for the failure message

    void note(int px, int py, const std::string& what) {
        if (std::count(firstProblems.begin(), firstProblems.end(), '\n') < 8)
            firstProblems += "  (" + std::to_string(px) + "," + std::to_string(py) + ") " + what + "\n";
    }
    std::string summary() const {
        char s[512];
        std::snprintf(
            s, sizeof s,
            "%dx%d: cpu hits %zu, gpu hits %zu, silhouette px %zu (mismatch %zu), coverage mismatch "
            "off-silhouette %zu, cpu-hit/gpu-miss %zu; compared %zu (ties %zu, grazing %zu): max depth rel %.3g "
            "(grazing %.3g), max normal angle %.3g rad, max colour %.3g, id mismatches %zu",
            width, height, cpuHits, gpuHits, silhouette, silhouetteMismatch, coverageMismatch, cpuHitGpuMiss, compared,
            ties, grazing, maxDepthRel, maxGrazingDepthRel, maxNormalAngle, maxColor, idMismatch);
        return s;
    }
};

FrameImages renderGpu(const StyledLines& lines, const Camera& cam, const Scene& scene, int w, int h) {
    auto technique = gl::createTechnique(scene, lines);
    gl::StageTimer timer;
    FrameImages gpu;
    technique->render(tc::FrameSetup{0, cam, w, h}, gpu, timer);
    timer.collect();
    return gpu;
}

Comparison compareWithReference(const StyledLines& lines, const Camera& cam, int w, int h) {
    Scene scene;  // default lighting, rasterized + opaque
    const FrameImages gpu = renderGpu(lines, cam, scene, w, h);
    const FrameImages cpu = renderReferenceOpaque(lines, cam, scene.lighting, w, h);
    const std::vector<char> flags = classifyPixels(lines, cam, w, h);
    const double sceneScale = glm::distance(cam.eye, lines.bounds.center());

    Comparison c;
    c.width = w;
    c.height = h;
    EXPECT_EQ(gpu.width, w);
    EXPECT_EQ(gpu.height, h);
    if (gpu.depth.size() != cpu.depth.size() || gpu.rgba.size() != cpu.rgba.size()) {
        ADD_FAILURE() << "GPU image has the wrong size";
        return c;
    }
    auto cpuHit = [&](int x, int y) { return cpu.id[std::size_t(y) * w + x] != kBackgroundId; };
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            const std::size_t i = std::size_t(py) * w + px;
            const bool ch = cpuHit(px, py);
            const bool gh = gpu.id[i] != kBackgroundId;
            c.cpuHits += ch;
            c.gpuHits += gh;
            bool mixed = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = px + dx, y = py + dy;
                    if (x >= 0 && y >= 0 && x < w && y < h && cpuHit(x, y) != ch) mixed = true;
                }
            c.silhouette += mixed;
            if (ch && !gh) ++c.cpuHitGpuMiss;
            if (ch != gh) {
                if (mixed)
                    ++c.silhouetteMismatch;
                else {
                    ++c.coverageMismatch;
                    c.note(px, py, ch ? "CPU hit, GPU background" : "GPU hit, CPU background");
                }
                continue;
            }
            if (!ch) {
                // Background must be exactly background on the GPU too.
                if (!std::isinf(gpu.depth[i]) || gpu.rgba[4 * i + 3] != 0.0f) c.note(px, py, "background not cleared");
                continue;
            }
            ++c.compared;
            const double dc = cpu.depth[i], dg = gpu.depth[i];
            const bool grazing = flags[i] & Grazing;
            const double rel = std::abs(dg - dc) / std::max(std::abs(dc), grazing ? 0.0 : sceneScale);
            if (grazing)
                c.maxGrazingDepthRel = std::max(c.maxGrazingDepthRel, rel);
            else
                c.maxDepthRel = std::max(c.maxDepthRel, rel);
            if (!(rel <= (grazing ? kGrazingDepthRelTolerance : kDepthRelTolerance))) {
                ++c.depthOver;
                c.note(px, py,
                       std::string(grazing ? "grazing " : "") + "depth cpu " + std::to_string(dc) + " gpu " +
                           std::to_string(dg));
            }
            if (!(dg > 0.0)) {
                ++c.depthOver;
                c.note(px, py, "depth not positive");
            }
            if (flags[i] & DepthTie) {
                ++c.ties;
                continue;
            }
            if (gpu.id[i] != cpu.id[i]) {
                ++c.idMismatch;
                c.note(px, py, "id cpu " + std::to_string(cpu.id[i]) + " gpu " + std::to_string(gpu.id[i]));
            }
            if (grazing) {
                ++c.grazing;
                continue;
            }
            const glm::vec3 nc(cpu.normal[3 * i], cpu.normal[3 * i + 1], cpu.normal[3 * i + 2]);
            const glm::vec3 ng(gpu.normal[3 * i], gpu.normal[3 * i + 1], gpu.normal[3 * i + 2]);
            const double angle = angleBetween(nc, ng);
            c.maxNormalAngle = std::max(c.maxNormalAngle, angle);
            if (!(angle <= kNormalAngleTolerance) || std::abs(glm::length(ng) - 1.0f) > 1e-4f) {
                ++c.normalOver;
                c.note(px, py, "normal angle " + std::to_string(angle));
            }
            double colorErr = 0;
            for (int k = 0; k < 4; ++k)
                colorErr = std::max(colorErr, double(std::abs(gpu.rgba[4 * i + k] - cpu.rgba[4 * i + k])));
            c.maxColor = std::max(c.maxColor, colorErr);
            if (!(colorErr <= kColorTolerance)) {
                ++c.colorOver;
                c.note(px, py, "colour error " + std::to_string(colorErr));
            }
        }
    return c;
}

// The checks every scene must pass; `minHits` guards against a camera that sees nothing.
void expectMatchesReference(const StyledLines& lines, const Camera& cam, int w, int h, std::size_t minHits,
                            const std::string& label) {
    SCOPED_TRACE(label);
    const Comparison c = compareWithReference(lines, cam, w, h);
    std::printf("[ measured ] %s: %s\n", label.c_str(), c.summary().c_str());
    EXPECT_GE(c.cpuHits, minHits) << "the view shows too little of the scene to test anything";
    EXPECT_EQ(c.coverageMismatch, 0u) << c.summary() << "\n" << c.firstProblems;
    EXPECT_EQ(c.depthOver, 0u) << c.summary() << "\n" << c.firstProblems;
    EXPECT_EQ(c.normalOver, 0u) << c.summary() << "\n" << c.firstProblems;
    EXPECT_EQ(c.idMismatch, 0u) << c.summary() << "\n" << c.firstProblems;
    EXPECT_EQ(c.colorOver, 0u) << c.summary() << "\n" << c.firstProblems;
    // Ties are where tubes interpenetrate and, mostly, shared joint spheres of a polyline: each
    // of the two segments colours the sphere by its own interpolation parameter, so the albedo
    // there depends on which one wins by float noise (measured: up to ~15 % of hit pixels with
    // radii varying 10x per vertex). At least half the pixels must get the full check, or the
    // id, normal and colour checks would be vacuous.
    EXPECT_GE(c.compared - c.ties - c.grazing, c.compared / 2) << c.summary();
}

using RoundedConeRendererTest = GlTest;

TEST_F(RoundedConeRendererTest, random_scenes_match_cpu_reference_perspective) {
    for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
        StyledLines lines = randomLineScene(seed);
        Camera cam = lookAt(eyeFromSeed(seed, 3.2f), {0, 0, 0});
        expectMatchesReference(lines, cam, 128, 96, 300, "perspective seed " + std::to_string(seed));
    }
}

TEST_F(RoundedConeRendererTest, random_scenes_match_cpu_reference_orthographic) {
    for (std::uint32_t seed : {5u, 6u, 7u}) {
        StyledLines lines = randomLineScene(seed);
        Camera cam = orthographic(eyeFromSeed(seed, 4.0f), {0, 0, 0}, 2.4f);
        expectMatchesReference(lines, cam, 128, 96, 300, "orthographic seed " + std::to_string(seed));
    }
}

TEST_F(RoundedConeRendererTest, many_short_segments_with_sharp_bends_match_cpu_reference) {
    RandomSceneOptions o;
    o.polylines = 4;
    o.minSegments = o.maxSegments = 10;  // 40 segments
    o.stepMin = 0.05f;
    o.stepMax = 0.2f;
    o.maxBendDeg = 150.0f;  // near-reversals: caps and laterals of neighbours overlap
    o.radiusMin = 0.01f;
    for (std::uint32_t seed : {11u, 12u}) {
        StyledLines lines = randomLineScene(seed, o);
        ASSERT_EQ(lines.segmentCount(), 40u);
        expectMatchesReference(lines, lookAt(eyeFromSeed(seed, 3.0f), {0, 0, 0}), 128, 96, 150,
                               "bent perspective seed " + std::to_string(seed));
        expectMatchesReference(lines, orthographic(eyeFromSeed(seed, 3.0f), {0, 0, 0}, 2.4f), 96, 72, 80,
                               "bent orthographic seed " + std::to_string(seed));
    }
}

// A wide tube along x with a thin one crossing it; the eye sits inside the wide one.
StyledLines tubeToLiveIn() {
    return makeStyledLines({
        {{{-3.0f, 0.0f, 0.0f}, 0.4f, {0.9f, 0.3f, 0.2f, 1}}, {{3.0f, 0.0f, 0.0f}, 0.25f, {0.2f, 0.4f, 0.9f, 1}}},
        {{{1.0f, -1.0f, -0.6f}, 0.05f, {0.3f, 0.8f, 0.3f, 1}}, {{1.2f, 1.0f, 0.6f}, 0.08f, {0.8f, 0.8f, 0.2f, 1}}},
    });
}

TEST_F(RoundedConeRendererTest, eye_inside_a_tube_sees_the_inner_wall_with_positive_depth) {
    const StyledLines lines = tubeToLiveIn();
    // Looking down the tube (the far cap and the crossing tube inside it) and across it (the near wall).
    for (const Camera& cam : {lookAt({-0.5f, 0.05f, 0.02f}, {3.0f, 0.1f, -0.05f}, {0, 1, 0}, 60.0f),
                              lookAt({0.0f, 0.1f, 0.0f}, {0.2f, -1.0f, 0.3f}, {1, 0, 0}, 60.0f)}) {
        ASSERT_LT(sdRoundedCone(cam.eye, {glm::vec3(lines.positionRadius[0]), lines.positionRadius[0].w,
                                          glm::vec3(lines.positionRadius[1]), lines.positionRadius[1].w}),
                  0.0f);
        const int w = 96, h = 72;
        expectMatchesReference(lines, cam, w, h, std::size_t(w) * h, "eye inside tube");
        FrameImages gpu = renderGpu(lines, cam, Scene{}, w, h);
        // Inside a closed tube every ray hits the wall: full coverage, depth > 0 everywhere.
        for (std::size_t i = 0; i < gpu.pixelCount(); ++i) {
            ASSERT_NE(gpu.id[i], kBackgroundId) << "pixel " << i;
            ASSERT_GT(gpu.depth[i], 0.0f) << "pixel " << i;
        }
    }
}

TEST_F(RoundedConeRendererTest, eye_inside_a_cap_sphere_sees_the_inner_wall) {
    // Eye behind x0 inside sphere 0 (r0 = 0.5), outside the lateral part; looking away from the
    // segment (only the sphere's inside) and along it.
    const StyledLines lines =
        makeStyledLines({{{{0, 0, 0}, 0.5f, {0.7f, 0.7f, 0.2f, 1}}, {{1.5f, 0, 0}, 0.2f, {0.2f, 0.6f, 0.8f, 1}}}});
    const glm::vec3 eye(-0.3f, 0.1f, 0.05f);
    for (const Camera& cam :
         {lookAt(eye, {-2.0f, 0.3f, 0.1f}, {0, 1, 0}, 70.0f), lookAt(eye, {1.5f, 0.0f, 0.0f}, {0, 1, 0}, 70.0f)}) {
        expectMatchesReference(lines, cam, 96, 72, 96 * 72, "eye inside cap sphere");
    }
}

TEST_F(RoundedConeRendererTest, view_exactly_and_nearly_along_a_segment_axis_matches_cpu_reference) {
    // Segment on the z axis, eye on the axis line in front of x1 (d x d0 = 0) or 1e-4 off it.
    const StyledLines lines = makeStyledLines({
        {{{0, 0, -1.0f}, 0.3f, {0.8f, 0.3f, 0.3f, 1}}, {{0, 0, 0}, 0.12f, {0.3f, 0.8f, 0.3f, 1}}},
        {{{0.6f, -0.4f, -0.5f}, 0.05f, {0.3f, 0.3f, 0.8f, 1}}, {{0.6f, 0.4f, -0.5f}, 0.05f, {0.3f, 0.3f, 0.8f, 1}}},
    });
    for (float offset : {0.0f, 1e-4f}) {
        const std::string what = offset == 0.0f ? "exactly along the axis" : "nearly along the axis";
        expectMatchesReference(lines, lookAt({offset, 0, 3.0f}, {offset, 0, 0}), 128, 96, 300, what + ", perspective");
        expectMatchesReference(lines, lookAt({offset, 0, 3.0f}, {0, 0, 0}), 128, 96, 300, what + ", perspective at x1");
        expectMatchesReference(lines, orthographic({offset, 0, 3.0f}, {offset, 0, 0}, 2.0f), 96, 72, 300,
                               what + ", orthographic");
        // Looking up the axis from behind x0: the big end in front.
        expectMatchesReference(lines, lookAt({0, offset, -4.0f}, {0, offset, 0}), 128, 96, 300, what + ", from behind");
    }
}

TEST_F(RoundedConeRendererTest, segment_crossing_the_eye_plane_matches_cpu_reference) {
    // Eye at z = 3 looking down -z; the first segment starts behind the eye (z = 5) and ends in
    // front of it, passing beside the eye; the polyline continues in view.
    const StyledLines lines = makeStyledLines({
        {{{0.4f, 0.2f, 5.0f}, 0.1f, {0.9f, 0.5f, 0.1f, 1}},
         {{0.3f, -0.2f, 0.0f}, 0.15f, {0.1f, 0.5f, 0.9f, 1}},
         {{-0.5f, -0.1f, -1.0f}, 0.1f, {0.5f, 0.9f, 0.1f, 1}}},
        {{{-0.8f, 0.5f, 4.0f}, 0.05f, {0.8f, 0.8f, 0.8f, 1}}, {{-0.3f, 0.4f, 2.0f}, 0.05f, {0.8f, 0.2f, 0.8f, 1}}},
    });
    expectMatchesReference(lines, lookAt({0, 0, 3.0f}, {0, 0, 0}, {0, 1, 0}, 60.0f), 128, 96, 1000,
                           "crossing the eye plane, perspective");
    // Orthographic rays start on the eye plane: the part behind it is cut off.
    expectMatchesReference(lines, orthographic({0, 0, 3.0f}, {0, 0, 0}, 2.0f), 96, 72, 300,
                           "crossing the eye plane, orthographic");
}

TEST_F(RoundedConeRendererTest, extreme_and_equal_radii_match_cpu_reference) {
    const StyledLines lines = makeStyledLines({
        // r0 >> r1 (50x), a long cone
        {{{-1.2f, 0.5f, 0}, 0.5f, {0.9f, 0.2f, 0.2f, 1}}, {{0.8f, 0.6f, 0.1f}, 0.01f, {0.2f, 0.9f, 0.2f, 1}}},
        // r0 == r1: a cylinder with two caps
        {{{-1.0f, -0.5f, 0.2f}, 0.15f, {0.2f, 0.2f, 0.9f, 1}}, {{1.2f, -0.6f, -0.3f}, 0.15f, {0.9f, 0.9f, 0.2f, 1}}},
        // one sphere (almost) containing the other: L = 0.3 < r0 - r1 = 0.35, then a normal cone
        {{{0.9f, 0.9f, -0.4f}, 0.4f, {0.5f, 0.5f, 0.5f, 1}},
         {{1.2f, 0.9f, -0.4f}, 0.05f, {0.9f, 0.5f, 0.1f, 1}},
         {{1.6f, 0.2f, -0.2f}, 0.3f, {0.1f, 0.5f, 0.9f, 1}}},
    });
    expectMatchesReference(lines, lookAt({0.3f, 0.2f, 4.0f}, {0.1f, 0.1f, 0}), 128, 96, 1000, "radii, front");
    expectMatchesReference(lines, lookAt({3.5f, 1.5f, 1.0f}, {0.1f, 0.1f, 0}, {0, 1, 0}), 128, 96, 1000,
                           "radii, oblique");
    expectMatchesReference(lines, orthographic({-1.0f, 3.0f, 2.0f}, {0.1f, 0.1f, 0}, 3.2f), 96, 72, 500,
                           "radii, orthographic");
}

TEST_F(RoundedConeRendererTest, billboards_cover_every_pixel_the_reference_hits_on_thin_tubes) {
    // 0.2 to 2 px wide tubes: most of their pixels are silhouette pixels, so a billboard that is
    // too tight by a fraction of a pixel loses hits the reference has.
    RandomSceneOptions o;
    o.polylines = 12;
    o.minSegments = 2;
    o.maxSegments = 4;
    o.radiusMin = 0.003f;
    o.radiusRatio = 10.0f;
    for (std::uint32_t seed : {21u, 22u}) {
        const StyledLines lines = randomLineScene(seed, o);
        for (const Camera& cam :
             {lookAt(eyeFromSeed(seed, 4.0f), {0, 0, 0}), orthographic(eyeFromSeed(seed, 4.0f), {0, 0, 0}, 3.0f)}) {
            const std::string label = std::string("thin tubes, ") +
                                      (cam.projection == Projection::Orthographic ? "orthographic" : "perspective") +
                                      " seed " + std::to_string(seed);
            SCOPED_TRACE(label);
            const Comparison c = compareWithReference(lines, cam, 128, 96);
            std::printf("[ measured ] %s: %s\n", label.c_str(), c.summary().c_str());
            EXPECT_GT(c.cpuHits, 100u);
            EXPECT_EQ(c.cpuHitGpuMiss, 0u) << c.summary() << "\n" << c.firstProblems;
            EXPECT_EQ(c.coverageMismatch, 0u) << c.summary() << "\n" << c.firstProblems;
        }
    }
}

TEST_F(RoundedConeRendererTest, describe_names_the_technique) {
    const StyledLines lines = randomLineScene(1);
    auto technique = gl::createTechnique(Scene{}, lines);
    const nlohmann::json d = technique->describe();
    ASSERT_TRUE(d.contains("technique")) << d.dump();
    EXPECT_EQ(d["technique"], "rasterized");
    EXPECT_EQ(d["transparency"], "opaque");
}

}  // namespace
}  // namespace tc::test
