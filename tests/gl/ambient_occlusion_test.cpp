// Line ambient occlusion end to end (gl/ambient_occlusion.h: voxelization -> density volume ->
// cone tracing in the deferred and k-buffer passes), through gl::createTechnique with
// render.ao.enabled and the per-pixel AO factor FrameImages::ao (1 on background).
//
// Scenes are hand-built straight tubes along x inside a fixed cube of bounds [-1, 1]^3 (the grid
// does not shrink around a thin tube), AO grid resolution 64 (voxel 2/63 ~ 0.0317), cone length
// 0.25 x the cube's diagonal (~27 voxels), default cones (3 at 45 degrees) and aperture (50).
// Views are orthographic from +z, so a pixel's world (x, y) is known and tube crests (the pixels
// within half a radius of an axis, normal within ~30 degrees of +z) can be picked out exactly.
// The occlusion model itself is tested on hand-made volumes in density_volume_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <glm/gtc/constants.hpp>
#include <map>
#include <string>
#include <vector>

#include "core/compositing.h"
#include "core/image_metrics.h"
#include "core/scene.h"
#include "core/technique.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "golden.h"
#include "io/image_io.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

namespace fs = std::filesystem;

constexpr int kAoResolution = 64;
constexpr float kVoxel = 2.0f / float(kAoResolution - 1);  // makeDensityGrid: extent / (res - 1)

TestPolyline tubeAlongX(float y, float z, float radius, float alpha = 1.0f, float x0 = -0.8f, float x1 = 0.8f) {
    const glm::vec4 color(0.8f, 0.8f, 0.8f, alpha);
    return {{{x0, y, z}, radius, color}, {{0.0f, y, z}, radius, color}, {{x1, y, z}, radius, color}};
}

// StyledLines with bounds fixed to the cube [-1, 1]^3, so every scene has the same AO grid.
StyledLines inUnitCube(const std::vector<TestPolyline>& polylines) {
    StyledLines lines = makeStyledLines(polylines);
    lines.bounds = Bounds{};
    lines.bounds.extend(glm::vec3(-1.0f), 0.0f);
    lines.bounds.extend(glm::vec3(1.0f), 0.0f);
    return lines;
}

Scene aoScene(bool ao = true) {
    Scene scene;
    scene.render.ao.enabled = ao;
    scene.render.ao.resolution = kAoResolution;
    scene.output.aovAo = ao;
    return scene;
}

// Orthographic, looking down -z at (cx, cy), `height` world units tall.
Camera topView(float cx, float cy, float height) {
    Camera cam;
    cam.projection = Projection::Orthographic;
    cam.target = {cx, cy, 0.0f};
    cam.eye = {cx, cy, 3.0f};
    cam.up = {0.0f, 1.0f, 0.0f};
    cam.orthoHeight = height;
    return cam;
}

FrameImages render(const Scene& scene, const StyledLines& lines, const Camera& cam, int w, int h) {
    auto technique = gl::createTechnique(scene, lines);
    gl::StageTimer timer;
    FrameImages out;
    technique->render(tc::FrameSetup{0, cam, w, h}, out, timer);
    timer.collect();
    return out;
}

// World (x, y) at the centre of pixel (px, py) of an orthographic top view.
glm::vec2 pixelWorld(const Camera& cam, int w, int h, int px, int py) {
    const Ray ray = pixelRay(cam, w, h, float(px), float(py));
    return {ray.origin.x, ray.origin.y};
}

struct AoStats {
    std::size_t pixels = 0;
    float min = 1.0f, max = 0.0f;
    double mean = 0.0;
};

// AO over the crest pixels of polyline `id` (axis at y = axisY): within half a radius of the axis
// in y, and away from the tube's ends by `endMargin` in x unless `keepEnds`.
AoStats crestAo(const FrameImages& img, const Camera& cam, std::uint32_t id, float axisY, float radius) {
    AoStats s;
    double sum = 0.0;
    for (int py = 0; py < img.height; ++py)
        for (int px = 0; px < img.width; ++px) {
            const std::size_t i = std::size_t(py) * img.width + px;
            if (img.id[i] != id) continue;
            const glm::vec2 p = pixelWorld(cam, img.width, img.height, px, py);
            if (std::abs(p.y - axisY) > 0.5f * radius) continue;
            ++s.pixels;
            s.min = std::min(s.min, img.ao[i]);
            s.max = std::max(s.max, img.ao[i]);
            sum += img.ao[i];
        }
    s.mean = s.pixels ? sum / double(s.pixels) : 0.0;
    return s;
}

// AO over every covered pixel.
AoStats coveredAo(const FrameImages& img) {
    AoStats s;
    double sum = 0.0;
    for (std::size_t i = 0; i < img.pixelCount(); ++i) {
        if (img.id[i] == kBackgroundId) continue;
        ++s.pixels;
        s.min = std::min(s.min, img.ao[i]);
        s.max = std::max(s.max, img.ao[i]);
        sum += img.ao[i];
    }
    s.mean = s.pixels ? sum / double(s.pixels) : 0.0;
    return s;
}

// ---------------------------------------------------------------------------------------------
// Isolated tube.

// A convex tube sees none of itself from its surface, so AO must read as unoccluded: >= 0.95 at
// every covered pixel, caps and silhouettes included. Measured: exactly 1 everywhere (the own-tube
// exclusion of shaders/cone_tracing.glsl, "Self-occlusion"; density_volume_test.cpp checks 720
// normals around the tube); with only a start offset of radius + 2 voxels it was min 0.93 / 0.82 /
// 0.70 for radii 0.5 / 1 / 2 voxels. 0.95 admits a small leak on another Mesa while failing that
// behaviour at radius >= 1 voxel.
// Radii 0.5, 1 and 2 voxels, the axis on voxel centres and on voxel faces (the two extremes of
// how the deposit spreads over the mip texels), viewed at its middle and at its end cap.
constexpr float kIsolatedMinAo = 0.95f;

TEST_F(GlTest, ao_of_an_isolated_tube_is_about_one_for_radii_of_half_to_two_voxels) {
    for (float radiusVoxels : {0.5f, 1.0f, 2.0f})
        for (float axisShift : {0.0f, 0.5f * kVoxel}) {
            const float r = radiusVoxels * kVoxel;
            const StyledLines lines = inUnitCube({tubeAlongX(axisShift, axisShift, r)});
            for (float cx : {0.0f, 0.8f}) {
                const Camera cam = topView(cx, axisShift, 12.0f * r);
                const FrameImages img = render(aoScene(), lines, cam, 64, 64);
                ASSERT_EQ(img.ao.size(), img.pixelCount());
                const AoStats s = coveredAo(img);
                std::printf(
                    "[ measured ] isolated tube r = %.1f voxels, axis shift %.1f voxels, view x %.1f: "
                    "%zu px, AO min %.4f mean %.4f\n",
                    radiusVoxels, axisShift / kVoxel, cx, s.pixels, s.min, s.mean);
                EXPECT_GT(s.pixels, 100u);
                EXPECT_GE(s.min, kIsolatedMinAo)
                    << "radius " << radiusVoxels << " voxels, axis shift " << axisShift / kVoxel << ", view x " << cx;
            }
        }
}

// ---------------------------------------------------------------------------------------------
// Bundle: 7 x 7 parallel tubes along x, radius 1.5 voxels, axis spacing 3 radii (a gap of one
// radius between neighbours). The three tubes above the centre one (y = 0, z > 0) are left out,
// so the top view sees the centre tube at the bottom of a slot, between the top layer's tubes.
constexpr float kBundleRadius = 1.5f * kVoxel;
constexpr float kBundleSpacing = 3.0f * kBundleRadius;

struct Bundle {
    StyledLines lines;
    std::uint32_t centreId = 0;
    std::vector<std::pair<std::uint32_t, float>> surface;  // top-layer tubes off the slot: id, y
};

Bundle makeBundle(float alpha = 1.0f) {
    Bundle b;
    std::vector<TestPolyline> polylines;
    for (int j = -3; j <= 3; ++j)
        for (int k = -3; k <= 3; ++k) {
            if (j == 0 && k > 0) continue;  // the slot
            const float y = j * kBundleSpacing, z = k * kBundleSpacing;
            const auto id = std::uint32_t(polylines.size());
            if (j == 0 && k == 0) b.centreId = id;
            if (k == 3 && std::abs(j) >= 2) b.surface.push_back({id, y});
            polylines.push_back(tubeAlongX(y, z, kBundleRadius, alpha));
        }
    b.lines = inUnitCube(polylines);
    return b;
}

// Centre tube at the bottom of the slot against the top layer's outer tubes (y = +-2, +-3
// spacings), crests only, middle third of the bundle's length (away from the open ends).
TEST_F(GlTest, ao_of_a_tube_inside_a_bundle_is_clearly_lower_than_at_its_surface) {
    const Bundle b = makeBundle();
    const Camera cam = topView(0.0f, 0.0f, 8.0f * kBundleSpacing);
    const FrameImages img = render(aoScene(), b.lines, cam, 96, 96);
    const AoStats centre = crestAo(img, cam, b.centreId, 0.0f, kBundleRadius);
    double surfaceMean = 0.0;
    float surfaceMin = 1.0f;
    for (auto [id, y] : b.surface) {
        const AoStats s = crestAo(img, cam, id, y, kBundleRadius);
        EXPECT_GT(s.pixels, 20u) << "surface tube at y " << y;
        surfaceMean += s.mean / double(b.surface.size());
        surfaceMin = std::min(surfaceMin, s.min);
    }
    std::printf("[ measured ] bundle: centre crest %zu px AO mean %.4f max %.4f; surface crests mean %.4f min %.4f\n",
                centre.pixels, centre.mean, centre.max, surfaceMean, surfaceMin);
    EXPECT_GT(centre.pixels, 20u);
    // Measured: centre mean 0.042, max 0.139 (the slot's opening is ~12 degrees wide across, open
    // along x: narrower than the 45-degree ring of cones); surface crests mean 0.916, min 0.808
    // (their neighbours in the top layer reach into the cones near the horizon). 0.5 leaves room
    // for other cone settings and Mesa versions while a bundle that stopped darkening its inside
    // would fail it.
    EXPECT_LT(centre.mean, surfaceMean - 0.5);
    EXPECT_LT(centre.max, surfaceMin);
}

// ---------------------------------------------------------------------------------------------
// Shell: a central tube (radius 1.5 voxels) inside a ring of 12 tubes at 0.2 (~6 voxels), then a
// second ring of 18 at 0.3, the tubes straight above the centre left out so the top view sees
// its crest. The shell gets denser by opacity (vertex alpha scales the deposited density; the
// opaque path draws every tube alike, so the centre's visible pixels stay the same) and then by
// count; the first stage is the centre tube alone.
StyledLines shellScene(float innerAlpha, float outerAlpha) {
    std::vector<TestPolyline> polylines{tubeAlongX(0.0f, 0.0f, kBundleRadius)};
    auto ring = [&](int count, float radius, float alpha) {
        if (alpha <= 0.0f) return;
        for (int i = 0; i < count; ++i) {
            const float phi = 2.0f * glm::pi<float>() * float(i) / float(count);
            if (std::abs(phi - 0.5f * glm::pi<float>()) < 0.3f) continue;  // keep the view from +z open
            polylines.push_back(tubeAlongX(radius * std::cos(phi), radius * std::sin(phi), kBundleRadius, alpha));
        }
    };
    ring(12, 0.2f, innerAlpha);
    ring(18, 0.3f, outerAlpha);
    return inUnitCube(polylines);
}

// Mean crest AO of the centre tube must fall by at least 0.01 per stage (measured steps are
// >= 0.05; 0.01 is well above float noise, which is ~1e-6 here).
TEST_F(GlTest, ao_decreases_monotonically_as_a_surrounding_shell_of_tubes_gets_denser) {
    const Camera cam = topView(0.0f, 0.0f, 0.25f);
    const std::pair<float, float> stages[] = {{0.0f, 0.0f}, {0.25f, 0.0f}, {0.5f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}};
    double previous = 2.0;
    for (auto [inner, outer] : stages) {
        const FrameImages img = render(aoScene(), shellScene(inner, outer), cam, 64, 64);
        const AoStats s = crestAo(img, cam, 0, 0.0f, kBundleRadius);
        std::printf("[ measured ] shell inner alpha %.2f, outer alpha %.2f: centre crest %zu px, AO mean %.4f\n", inner,
                    outer, s.pixels, s.mean);
        ASSERT_GT(s.pixels, 50u);
        if (inner == 0.0f) {
            EXPECT_EQ(s.mean, 1.0);  // isolated: exactly unoccluded
        }
        EXPECT_LT(s.mean, previous - 0.01) << "inner " << inner << ", outer " << outer;
        previous = s.mean;
    }
}

// ---------------------------------------------------------------------------------------------
// AO on and off, opaque: the G-buffer AOVs do not depend on AO (bit-exact); AO only scales
// ambient + diffuse, so every colour channel is <= the one without AO (+1e-6 for the float
// shading of albedo * ao vs albedo at ao = 1, which are the same product) and some are clearly
// darker; AO is in [0, 1] and exactly 1 on background.
TEST_F(GlTest, opaque_ao_keeps_depth_normal_and_id_aovs_and_only_darkens_colour) {
    const Bundle b = makeBundle();
    const Camera cam = topView(0.1f, 0.05f, 10.0f * kBundleSpacing);
    const FrameImages on = render(aoScene(true), b.lines, cam, 80, 64);
    const FrameImages off = render(aoScene(false), b.lines, cam, 80, 64);
    ASSERT_EQ(on.pixelCount(), off.pixelCount());
    EXPECT_TRUE(off.ao.empty());
    ASSERT_EQ(on.ao.size(), on.pixelCount());
    EXPECT_EQ(std::memcmp(on.depth.data(), off.depth.data(), on.depth.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(on.normal.data(), off.normal.data(), on.normal.size() * sizeof(float)), 0);
    EXPECT_EQ(on.id, off.id);
    float maxDarkening = 0.0f, maxBrightening = 0.0f;
    for (std::size_t i = 0; i < on.pixelCount(); ++i) {
        ASSERT_GE(on.ao[i], 0.0f);
        ASSERT_LE(on.ao[i], 1.0f);
        if (on.id[i] == kBackgroundId) {
            EXPECT_EQ(on.ao[i], 1.0f);
        }
        for (int c = 0; c < 4; ++c) {
            const float d = off.rgba[4 * i + c] - on.rgba[4 * i + c];
            maxDarkening = std::max(maxDarkening, d);
            maxBrightening = std::max(maxBrightening, -d);
        }
    }
    std::printf("[ measured ] opaque AO on vs off: max darkening %.4f, max brightening %.3g\n", maxDarkening,
                maxBrightening);
    EXPECT_LE(maxBrightening, 1e-6f);
    EXPECT_GT(maxDarkening, 0.1f);
}

// k-buffer (k = 8) with AO against without, tubes at opacity 0.5: AO multiplies each fragment's
// albedo before insertion, and compositing the same alphas is monotonic in colour, so no channel
// may get brighter by more than one RGBA8 step of the k-buffer (1/255: both sides round their
// fragments independently); some must get clearly darker.
TEST_F(GlTest, kbuffer_with_ao_darkens_relative_to_without) {
    const Bundle b = makeBundle(0.5f);
    const Camera cam = topView(0.1f, 0.05f, 10.0f * kBundleSpacing);
    Scene on = aoScene(true), off = aoScene(false);
    on.output.aovAo = false;  // the transparent path has no AO AOV
    for (Scene* s : {&on, &off}) {
        s->render.transparency = Transparency::KBuffer;
        s->render.kbufferK = 8;
    }
    const FrameImages a = render(on, b.lines, cam, 80, 64);
    const FrameImages n = render(off, b.lines, cam, 80, 64);
    ASSERT_EQ(a.rgba.size(), n.rgba.size());
    float maxDarkening = 0.0f, maxBrightening = 0.0f;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) {
        if (i % 4 == 3) {
            EXPECT_EQ(a.rgba[i], n.rgba[i]) << "alpha must not depend on AO";
            continue;
        }
        maxDarkening = std::max(maxDarkening, n.rgba[i] - a.rgba[i]);
        maxBrightening = std::max(maxBrightening, a.rgba[i] - n.rgba[i]);
    }
    std::printf("[ measured ] k-buffer AO on vs off: max darkening %.4f, max brightening %.3g\n", maxDarkening,
                maxBrightening);
    EXPECT_LE(maxBrightening, 1.0f / 255.0f + 1e-6f);
    EXPECT_GT(maxDarkening, 0.05f);
}

// ---------------------------------------------------------------------------------------------
// Determinism: the cone sets are fixed (no per-pixel rotation) and the volume is bit-identical
// for any thread count, so two techniques built from the same scene give bit-identical AO and
// colour, and so does rendering the same technique twice.
TEST_F(GlTest, opaque_ao_frames_are_bit_identical_across_renders_and_techniques) {
    const Bundle b = makeBundle();
    const Camera cam = topView(0.1f, 0.05f, 10.0f * kBundleSpacing);
    auto technique = gl::createTechnique(aoScene(), b.lines);
    gl::StageTimer timer;
    FrameImages first, second;
    technique->render(tc::FrameSetup{0, cam, 80, 64}, first, timer);
    technique->render(tc::FrameSetup{0, cam, 80, 64}, second, timer);
    timer.collect();
    const FrameImages third = render(aoScene(), b.lines, cam, 80, 64);
    for (const FrameImages* other : {static_cast<const FrameImages*>(&second), &third}) {
        ASSERT_EQ(other->ao.size(), first.ao.size());
        EXPECT_EQ(std::memcmp(first.ao.data(), other->ao.data(), first.ao.size() * sizeof(float)), 0);
        EXPECT_EQ(std::memcmp(first.rgba.data(), other->rgba.data(), first.rgba.size() * sizeof(float)), 0);
    }
}

// ---------------------------------------------------------------------------------------------
// Cached AO (render.ao.cache "precomputed", the default; gl/ao_line_cache.h) against cone tracing at
// every shaded point ("none"), per covered pixel of the opaque AO AOV (same G-buffer, so the same
// visible surface) and per colour channel of a k-buffer frame. Scenes: the bundle seen obliquely
// (long straight segments: 14 samples each) and a tangle of random bent polylines with segments
// of 1-2.5 voxels (2-3 samples), radius ~1 voxel, in perspective.
struct AoDifference {
    std::size_t pixels = 0;
    double mean = 0.0;
    float max = 0.0f;
    std::size_t polylines = 0;
    double polylineMean = 0.0, polylineMax = 0.0;
};

AoDifference aoDifference(const FrameImages& a, const FrameImages& b) {
    AoDifference d;
    for (std::size_t i = 0; i < a.pixelCount(); ++i) {
        if (a.id[i] == kBackgroundId) continue;
        const float e = std::abs(a.ao[i] - b.ao[i]);
        ++d.pixels;
        d.mean += e;
        d.max = std::max(d.max, e);
    }
    d.mean = d.pixels ? d.mean / double(d.pixels) : 0.0;
    // Per visible polyline with >= 20 pixels: |mean AO of a - mean AO of b|.
    std::map<std::uint32_t, std::array<double, 3>> perId;  // sum a, sum b, count
    for (std::size_t i = 0; i < a.pixelCount(); ++i) {
        if (a.id[i] == kBackgroundId) continue;
        auto& v = perId[a.id[i]];
        v[0] += a.ao[i];
        v[1] += b.ao[i];
        v[2] += 1.0;
    }
    for (const auto& [id, v] : perId) {
        if (v[2] < 20.0) continue;
        const double e = std::abs(v[0] - v[1]) / v[2];
        ++d.polylines;
        d.polylineMean += e;
        d.polylineMax = std::max(d.polylineMax, e);
    }
    d.polylineMean = d.polylines ? d.polylineMean / double(d.polylines) : 0.0;
    return d;
}

StyledLines tangleScene() {
    RandomSceneOptions o;
    o.polylines = 60;
    o.minSegments = 10;
    o.maxSegments = 30;
    o.radiusMin = 1.0f * kVoxel;
    o.radiusRatio = 1.5f;
    o.stepMin = 1.0f * kVoxel;
    o.stepMax = 2.5f * kVoxel;
    o.maxBendDeg = 40.0f;
    o.extent = 0.3f;
    StyledLines lines = randomLineScene(7, o);
    lines.bounds = Bounds{};
    lines.bounds.extend(glm::vec3(-1.0f), 0.0f);
    lines.bounds.extend(glm::vec3(1.0f), 0.0f);
    return lines;
}

Camera obliqueView(glm::vec3 target, float distance) {
    Camera cam;
    cam.eye = target + distance * glm::normalize(glm::vec3(1.3f, -0.8f, 1.0f));
    cam.target = target;
    cam.up = {0.0f, 0.0f, 1.0f};
    cam.fovYDeg = 40.0f;
    return cam;
}

// Measured (llvmpipe of Debian 12, 8 azimuths, 1 sample per 2 voxels of segment length, shared
// at joints), with the exact tracer's own-tube exclusion (smooth in the normal):
//   bundle: per pixel |diff| mean 0.082, max 0.635; per polyline |mean diff| mean 0.076, max 0.140
//   tangle: per pixel |diff| mean 0.045, max 0.485; per polyline |mean diff| mean 0.020, max 0.141
//   k-buffer tangle: composited colour |diff| mean 0.0084.
// (With the former level-switching exclusion the exact AO jumped with the normal, 0.334 / 0.666 /
// 0.002 at 28 / 51 / 62 degrees on one tube, and the means were 0.118 / 0.127 / 0.0234.) What is
// left is the cache's interpolation: 8 azimuths 45 degrees apart against AO that falls from 1 to
// ~0 within ~60 degrees where a tube touches its neighbours (the bundle's crevices). Limits:
// about 1.5x the measured values (a cache that lost its azimuth or position dependence would
// read each tube's ring mean and miss the bundle's dark crevices); the per-pixel maximum is
// reported, not bounded.
constexpr double kCachedMeanAoError = 0.12;
constexpr double kCachedPolylineMeanAoError = 0.11;
constexpr double kCachedPolylineMaxAoError = 0.21;
constexpr double kCachedKBufferColourError = 0.0125;

TEST_F(GlTest, cached_ao_agrees_with_cone_traced_ao_per_pixel) {
    Scene exact = aoScene();
    exact.render.ao.cache = AoSpec::Cache::None;
    const Scene cached = aoScene();
    ASSERT_EQ(cached.render.ao.cache, AoSpec::Cache::Precomputed);  // the default
    const Bundle b = makeBundle();
    const StyledLines tangle = tangleScene();
    const struct {
        const char* name;
        const StyledLines& lines;
        Camera cam;
    } cases[] = {{"bundle", b.lines, obliqueView({0.35f, 0.0f, 0.0f}, 2.0f)},
                 {"tangle", tangle, obliqueView({0.0f, 0.0f, 0.0f}, 1.6f)}};
    for (const auto& c : cases) {
        const FrameImages e = render(exact, c.lines, c.cam, 128, 96);
        const FrameImages a = render(cached, c.lines, c.cam, 128, 96);
        ASSERT_EQ(a.id, e.id) << c.name;
        const AoDifference d = aoDifference(a, e);
        const AoStats s = coveredAo(e);
        std::printf(
            "[ measured ] cached vs cone traced AO, %s: %zu px (exact AO mean %.4f min %.4f), |diff| mean "
            "%.4f max %.4f; per polyline (%zu) |mean diff| mean %.4f max %.4f\n",
            c.name, d.pixels, s.mean, s.min, d.mean, d.max, d.polylines, d.polylineMean, d.polylineMax);
        EXPECT_GT(d.pixels, 1000u) << c.name;
        EXPECT_LT(s.mean, 0.9) << c.name << ": the scene must be clearly occluded for the comparison to mean anything";
        EXPECT_LE(d.mean, kCachedMeanAoError) << c.name;
        EXPECT_GT(d.polylines, 30u) << c.name;
        EXPECT_LE(d.polylineMean, kCachedPolylineMeanAoError) << c.name;
        EXPECT_LE(d.polylineMax, kCachedPolylineMaxAoError) << c.name;
    }
}

// The transparent path reads the same cache per fragment before k-buffer insertion: the
// composited colours of the tangle at opacity 0.5 agree on average.
TEST_F(GlTest, cached_ao_agrees_with_cone_traced_ao_in_the_kbuffer) {
    StyledLines tangle = tangleScene();
    for (glm::vec4& c : tangle.color) c.w = 0.5f;
    Scene exact = aoScene(), cached = aoScene();
    exact.render.ao.cache = AoSpec::Cache::None;
    for (Scene* s : {&exact, &cached}) {
        s->render.transparency = Transparency::KBuffer;
        s->render.kbufferK = 8;
        s->output.aovAo = false;
    }
    const Camera cam = obliqueView({0.0f, 0.0f, 0.0f}, 1.6f);
    const FrameImages e = render(exact, tangle, cam, 128, 96);
    const FrameImages a = render(cached, tangle, cam, 128, 96);
    ASSERT_EQ(a.rgba.size(), e.rgba.size());
    double mean = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) {
        if (i % 4 == 3) {
            EXPECT_EQ(a.rgba[i], e.rgba[i]) << "alpha must not depend on AO";
            continue;
        }
        if (e.rgba[i - i % 4 + 3] == 0.0f) continue;
        mean += std::abs(a.rgba[i] - e.rgba[i]);
        ++n;
    }
    mean = n ? mean / double(n) : 0.0;
    std::printf("[ measured ] cached vs cone traced AO, k-buffer tangle: %zu channels, |colour diff| mean %.4f\n", n,
                mean);
    EXPECT_GT(n, 3000u);
    EXPECT_LE(mean, kCachedKBufferColourError);
}

// ---------------------------------------------------------------------------------------------
// Golden: the bundle of the contrast test seen obliquely (perspective), AO on, opaque, 128 x 96,
// over a dark background, same thresholds and TUBECAST_BLESS mechanism as golden_test.cpp
// (tests/golden/README.md; golden.h).
using AoGoldenTest = GlTest;

TEST_F(AoGoldenTest, opaque_bundle_with_ao_at_128x96_matches_golden) {
    const Bundle b = makeBundle();
    Camera cam;
    cam.eye = {1.5f, -0.9f, 1.1f};
    cam.target = {0.35f, 0.0f, 0.0f};
    cam.up = {0.0f, 0.0f, 1.0f};
    cam.fovYDeg = 40.0f;
    // The golden was blessed with cone tracing per pixel; the cached default differs from it by
    // its interpolation (cached_ao_agrees_with_cone_traced_ao_per_pixel bounds that), so the
    // golden keeps pinning the exact tracer.
    Scene scene = aoScene();
    scene.render.ao.cache = AoSpec::Cache::None;
    FrameImages img = render(scene, b.lines, cam, 128, 96);
    compositeUnder(img, glm::vec4(0.1f, 0.1f, 0.12f, 1.0f));
    expectMatchesGolden(img, "ao_bundle_128x96");
}

}  // namespace
}  // namespace tc::test
