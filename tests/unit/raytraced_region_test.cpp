// Data-parallel rendering in the CPU ray tracer (rt/) without MPI, and the core parts of region
// clipping (core/region.h, the density owner rule of core/voxel_density.h): a scene split by hand
// into 2, 3 and 4 region boxes (tests/region_split.h), each region traced by its own renderer on
// the share of the data a rank would hold (or on all of it), composited on the CPU as IceT does
// (opaque: nearest depth; transparent: "under" in view order) and compared with the full render.
//
// Opaque composites are asked to be bit-identical: a region's rays find the full frame's visible
// surface when its point lies in the box (the same Embree hit, refined by the same code) and only
// farther surfaces otherwise. Exact transparent composites (alpha cutoff 1) are asked for PSNR
// >= 50 dB: the regions' "under" sums associate differently (float ulps, ~1e-7); a lost or doubled
// hit moves a pixel by alpha x colour, >= 1e-2 here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/halo.h"
#include "core/image_metrics.h"
#include "core/region.h"
#include "core/stage_sink.h"
#include "core/voxel_density.h"
#include "region_split.h"
#include "rt/raytraced_particles.h"
#include "rt/raytraced_renderer.h"
#include "rt/techniques.h"
#include "test_scenes.h"

namespace tc {
namespace {

using test::compositeNearest;
using test::compositeUnder;
using test::Layout;
using test::layouts;
using test::linesReaching;
using test::lookAt;
using test::orthographic;
using test::RegionSplit;
using test::spheresReaching;

constexpr double kMinPsnr = 50.0;
constexpr float kInf = std::numeric_limits<float>::infinity();

// --- core/region.h ---------------------------------------------------------------------------

TEST(Region, boxes_are_half_open_and_the_default_holds_every_finite_point) {
    RegionBox b;
    EXPECT_TRUE(b.unbounded());
    EXPECT_TRUE(b.contains({1e30f, -1e30f, 0.0f}));
    b.lo = {0, 0, 0};
    b.hi = {1, 1, 1};
    EXPECT_TRUE(b.contains({0, 0, 0}));
    EXPECT_FALSE(b.contains({1, 0.5f, 0.5f}));  // hi is the next region's
    EXPECT_FALSE(b.contains({std::nextafter(0.0f, -1.0f), 0.5f, 0.5f}));
    // reaches: a closed box touching lo reaches, one ending at hi does not hold any point of it.
    EXPECT_TRUE(b.reaches({-2, -2, -2}, {0, 0, 0}));
    EXPECT_FALSE(b.reaches({1, 0, 0}, {2, 1, 1}));
    EXPECT_TRUE(b.reaches({0.99f, 0, 0}, {2, 1, 1}));
}

TEST(Region, ray_interval_handles_parallel_rays_faces_and_infinite_boxes) {
    RegionBox b;
    b.lo = {-1, -1, -kInf};
    b.hi = {1, 1, 0};
    // Along +z from z = -5: inside for every t up to z = 0.
    RayInterval iv = rayInterval({{0, 0, -5}, {0, 0, 1}}, b);
    EXPECT_EQ(iv.t0, -kInf);
    EXPECT_EQ(iv.t1, 5.0f);
    // Parallel to the x faces, on a face: inside (closed interval), no NaN.
    iv = rayInterval({{1, 0, -5}, {0, 0, 1}}, b);
    EXPECT_FALSE(iv.empty());
    EXPECT_EQ(iv.t1, 5.0f);
    // Parallel and outside: empty.
    EXPECT_TRUE(rayInterval({{1.5f, 0, -5}, {0, 0, 1}}, b).empty());
    // Oblique: enters at x = -1 (t = 2 sqrt 2), leaves at z = 0 (t = 3 sqrt 2) before x = 1.
    const glm::vec3 d = glm::normalize(glm::vec3(1, 0, 1));
    iv = rayInterval({{-3, 0, -3}, d}, b);
    EXPECT_NEAR(iv.t0, 2.0f * std::sqrt(2.0f), 1e-5f);
    EXPECT_NEAR(iv.t1, 3.0f * std::sqrt(2.0f), 1e-5f);
    EXPECT_TRUE(rayInterval({{-3, 5, -3}, d}, b).empty());
    // The unbounded box: everything.
    iv = rayInterval({{0, 0, 0}, {0, 1, 0}}, RegionBox{});
    EXPECT_EQ(iv.t0, -kInf);
    EXPECT_EQ(iv.t1, kInf);
}

// --- Scenes ----------------------------------------------------------------------------------

// The layout styleLines builds: contiguous polylines, segments (v, v + 1), flags at the ends.
// Random bent polylines (4..9 vertices, steps 0.2..0.45, turns up to ~70 degrees, radii
// 0.04..0.12) in [-0.7, 0.7]^3, colours and alpha in [alphaLo, alphaHi] per vertex; only
// std::mt19937's raw output is used, so the scene is the same with every standard library.
StyledLines randomLines(unsigned seed, int count, float alphaLo, float alphaHi, bool constantRadius = false) {
    std::mt19937 rng(seed);
    auto u = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) * (1.0f / 16777216.0f); };
    StyledLines l;
    for (int p = 0; p < count; ++p) {
        glm::vec3 x(u(-0.7f, 0.7f), u(-0.7f, 0.7f), u(-0.7f, 0.7f));
        glm::vec3 d = glm::normalize(glm::vec3(u(-1, 1), u(-1, 1), u(-1, 1)) + glm::vec3(1e-3f));
        const float r0 = u(0.04f, 0.12f);
        const int n = 4 + int(rng() % 6u);
        const std::uint32_t begin = std::uint32_t(l.positionRadius.size());
        for (int k = 0; k < n; ++k) {
            const float r = constantRadius ? r0 : u(0.04f, 0.12f);
            l.positionRadius.emplace_back(x, r);
            l.color.emplace_back(u(0.1f, 1.0f), u(0.1f, 1.0f), u(0.1f, 1.0f), u(alphaLo, alphaHi));
            l.polylineId.push_back(std::uint32_t(p));
            l.flags.push_back((k == 0 ? FirstOfPolyline : 0u) | (k + 1 == n ? LastOfPolyline : 0u));
            l.bounds.extend(x, r);
            l.maxRadius = std::max(l.maxRadius, r);
            if (k > 0) {
                l.segmentVertices.push_back(begin + std::uint32_t(k) - 1);
                l.segmentVertices.push_back(begin + std::uint32_t(k));
            }
            const glm::vec3 axis =
                glm::normalize(glm::cross(d, glm::vec3(u(-1, 1), u(-1, 1), u(-1, 1))) + glm::vec3(1e-4f));
            const float a = u(-1.2f, 1.2f);
            d = glm::normalize(d * std::cos(a) + glm::cross(axis, d) * std::sin(a) +
                               axis * glm::dot(axis, d) * (1.0f - std::cos(a)));
            x += u(0.2f, 0.45f) * d;
        }
    }
    return l;
}

Camera camera(glm::vec3 eye, glm::vec3 target = {0, 0, 0}, Projection projection = Projection::Perspective) {
    return projection == Projection::Perspective ? lookAt(eye, target) : orthographic(eye, target, 2.4f);
}

Scene raytracedScene(Transparency t, bool capClipping = true) {
    Scene s;
    s.file = "scene.json";
    s.render.technique = RenderTechnique::Raytraced;
    s.render.transparency = t;
    s.render.capClipping = capClipping;
    s.render.raytracedAlphaCutoff = 1.0f;
    // Regions always take the exact surface; the whole frame they compose to is that one.
    s.render.raytracedExactSurface = true;
    s.output.aovDepth = s.output.aovNormal = s.output.aovId = true;  // the composites compare them all
    return s;
}

// Through the technique's descriptor, as the frame loop makes it.
// `all`: the whole dataset, whose bounds and largest radius every rank gets (none: one process).
FrameImages trace(const Scene& scene, const StyledLines& lines, const Camera& cam, int w, int h,
                  const RegionBox& box = {}, const StyledLines* all = nullptr, const TechniqueHooks& hooks = {}) {
    TechniqueData data;
    data.lines = &lines;
    data.region = box;
    if (all) {
        data.bounds = all->bounds;
        data.maxRadius = all->maxRadius;
    }
    auto technique = rt::raytracedTechnique().create(scene, data, hooks);
    FrameImages img;
    CpuStageTimer timer;
    technique->render(FrameSetup{0, cam, w, h}, img, timer);
    return img;
}

enum class Share { Reaching, All };

std::vector<FrameImages> traceRegions(const Scene& scene, const StyledLines& lines, const Camera& cam, int w, int h,
                                      const RegionSplit& split, Share share) {
    std::vector<FrameImages> out;
    for (const RegionBox& box : split.boxes())
        out.push_back(trace(scene, share == Share::All ? lines : linesReaching(lines, box), cam, w, h, box, &lines));
    return out;
}

std::size_t differingPixels(const FrameImages& a, const FrameImages& b, float* maxRgba = nullptr,
                            float* maxAo = nullptr) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.pixelCount(); ++i) {
        bool differs = std::memcmp(&a.rgba[4 * i], &b.rgba[4 * i], 16) != 0 ||
                       std::memcmp(&a.depth[i], &b.depth[i], 4) != 0 ||
                       std::memcmp(&a.normal[3 * i], &b.normal[3 * i], 12) != 0 || a.id[i] != b.id[i];
        if (!a.ao.empty()) differs = differs || std::memcmp(&a.ao[i], &b.ao[i], 4) != 0;
        n += differs;
        for (int c = 0; c < 4 && maxRgba; ++c)
            *maxRgba = std::max(*maxRgba, std::abs(a.rgba[4 * i + c] - b.rgba[4 * i + c]));
        if (maxAo && !a.ao.empty()) *maxAo = std::max(*maxAo, std::abs(a.ao[i] - b.ao[i]));
    }
    return n;
}

std::size_t covered(const FrameImages& f) {
    std::size_t n = 0;
    for (std::uint32_t id : f.id) n += id != kBackgroundId;
    return n;
}

// --- Tubes -----------------------------------------------------------------------------------

// Seed 21: 70 polylines, 377 segments; the planes cut 68 (2 regions), 104 (3) and 124 (4) of
// them (asserted). Perspective and orthographic views. Each region's image must also show nothing
// outside its box (Z compositing alone would hide a region that draws too much).
TEST(RaytracedRegions, opaque_regions_z_composite_bit_identically_to_the_full_frame) {
    const StyledLines lines = randomLines(21, 70, 1.0f, 1.0f);
    const int w = 96, h = 72;
    ASSERT_EQ(lines.segmentCount(), 377u);
    const std::size_t expectedCrossing[] = {68, 104, 124};
    const Scene scene = raytracedScene(Transparency::Opaque);
    for (const Camera& cam :
         {camera({1.6f, 1.2f, 2.4f}), camera({-1.0f, 2.0f, -1.5f}, {0, 0, 0}, Projection::Orthographic)}) {
        const FrameImages full = trace(scene, lines, cam, w, h);
        ASSERT_GT(covered(full), std::size_t(w * h / 4));
        int l = 0;
        for (const Layout& layout : layouts()) {
            const std::size_t crossing = test::segmentsCrossingRegions(lines, layout.split.boxes());
            EXPECT_EQ(crossing, expectedCrossing[l++]) << layout.name;
            for (Share share : {Share::Reaching, Share::All}) {
                const std::string label = std::string(layout.name) + (share == Share::All ? ", all" : ", reaching") +
                                          (cam.projection == Projection::Orthographic ? ", orthographic" : "");
                const std::vector<FrameImages> regions = traceRegions(scene, lines, cam, w, h, layout.split, share);
                for (std::size_t r = 0; r < regions.size(); ++r) {
                    EXPECT_GT(covered(regions[r]), 50u) << label;
                    // Z compositing would hide a region drawing too much; its own image does not.
                    EXPECT_EQ(test::pixelsOutsideBox(regions[r], cam, layout.split.boxes()[r]), 0u)
                        << label << ", region " << r;
                }
                const std::size_t d = differingPixels(compositeNearest(regions), full);
                std::printf("[ measured ] raytraced opaque, %s (%zu of %zu segments cross): %zu differing pixels\n",
                            label.c_str(), crossing, lines.segmentCount(), d);
                EXPECT_EQ(d, 0u) << label;
            }
        }
    }
}

// Exact transparency (alpha cutoff 1), with joined tubes (cap clipping) and with separate rounded
// cones; the first-surface AOVs Z-composite exactly.
TEST(RaytracedRegions, exact_transparent_regions_composited_in_view_order_match_the_full_frame) {
    const StyledLines lines = randomLines(22, 50, 0.2f, 0.6f);
    const int w = 80, h = 60;
    for (const Camera& cam :
         {camera({1.4f, -1.1f, 2.4f}), camera({2.0f, 1.0f, 1.0f}, {0, 0, 0}, Projection::Orthographic)}) {
        for (bool capClipping : {true, false}) {
            const Scene scene = raytracedScene(Transparency::DepthPeeling, capClipping);
            const FrameImages full = trace(scene, lines, cam, w, h);
            for (const Layout& layout : layouts()) {
                const std::string label = std::string(layout.name) +
                                          (capClipping ? ", joined tubes" : ", separate cones") +
                                          (cam.projection == Projection::Orthographic ? ", orthographic" : "");
                const std::vector<FrameImages> regions =
                    traceRegions(scene, lines, cam, w, h, layout.split, Share::Reaching);
                const FrameImages composite = compositeUnder(regions, layout.split.frontToBack(cam));
                const ImageMetrics m = compareRgba(composite.rgba, full.rgba);
                std::printf("[ measured ] raytraced transparent, %s: PSNR %.1f dB, max |diff| %.2e\n", label.c_str(),
                            m.psnr, m.maxError);
                EXPECT_GE(m.psnr, kMinPsnr) << label;
                EXPECT_EQ(composite.depth, full.depth) << label;
                EXPECT_EQ(composite.id, full.id) << label;
                EXPECT_EQ(composite.normal, full.normal) << label;
            }
        }
    }
}

// style.halo: a segment goes to every region its ring reaches (the data-parallel decomposition's
// haloReach), and a fragment to the region holding its surface point (a ring's: where the ray
// enters it). So each region composites what it would with the whole data set. Against the full
// frame the composite differs where a ring's pushed-back depth lies behind fragments of the next
// region in view order: sort-last compositing puts the whole nearer region first, one process
// sorts by depth (the GL path's rule too). Measured here: 41-47 dB with the default push of 4
// radii, 49-58 dB with none.
TEST(RaytracedRegions, halo_regions_hold_every_ring_that_reaches_them_and_composite_close_to_the_full_frame) {
    const StyledLines lines = randomLines(22, 50, 0.2f, 0.6f);
    const int w = 80, h = 60;
    Scene scene = raytracedScene(Transparency::DepthPeeling);
    scene.style.halo.enabled = true;
    scene.style.halo.width = 0.8f;
    scene.style.halo.color = glm::vec3(0.9f, 0.6f, 0.1f);
    const float reach = haloReach(scene.style.halo);
    const Camera cam = camera({1.4f, -1.1f, 2.4f});
    const FrameImages full = trace(scene, lines, cam, w, h);
    for (const Layout& layout : layouts()) {
        SCOPED_TRACE(layout.name);
        std::vector<FrameImages> reaching, whole;
        for (const RegionBox& box : layout.split.boxes()) {
            reaching.push_back(trace(scene, linesReaching(lines, box, reach), cam, w, h, box, &lines));
            whole.push_back(trace(scene, lines, cam, w, h, box, &lines));
        }
        const auto order = layout.split.frontToBack(cam);
        const FrameImages composite = compositeUnder(reaching, order);
        // The segments that reach a region by their ring only are there.
        EXPECT_EQ(differingPixels(composite, compositeUnder(whole, order)), 0u);
        const ImageMetrics m = compareRgba(composite.rgba, full.rgba);
        std::printf("[ measured ] raytraced halos, %s: PSNR %.1f dB against the full frame\n", layout.name, m.psnr);
        EXPECT_GE(m.psnr, 38.0);
    }
}

// The eye inside a tube that crosses the face x = 0, and joints on the face: a thick tube along x
// and two polylines bending at x = 0 and x = +-0.01.
StyledLines faceLines() {
    StyledLines l;
    auto polyline = [&](std::vector<glm::vec4> points, glm::vec4 color) {
        const std::uint32_t begin = std::uint32_t(l.positionRadius.size()),
                            id = l.polylineId.empty() ? 0u : l.polylineId.back() + 1;
        for (std::size_t k = 0; k < points.size(); ++k) {
            l.positionRadius.push_back(points[k]);
            l.color.push_back(color);
            l.polylineId.push_back(id);
            l.flags.push_back((k == 0 ? FirstOfPolyline : 0u) | (k + 1 == points.size() ? LastOfPolyline : 0u));
            l.bounds.extend(glm::vec3(points[k]), points[k].w);
            l.maxRadius = std::max(l.maxRadius, points[k].w);
            if (k > 0) {
                l.segmentVertices.push_back(begin + std::uint32_t(k) - 1);
                l.segmentVertices.push_back(begin + std::uint32_t(k));
            }
        }
    };
    polyline({{-1.2f, 0.0f, 0.0f, 0.25f}, {1.2f, 0.05f, 0.0f, 0.25f}}, {0.85f, 0.5f, 0.2f, 0.45f});
    polyline({{-0.6f, -0.5f, 0.3f, 0.12f},
              {0.0f, -0.35f, 0.25f, 0.12f},
              {0.45f, -0.5f, 0.35f, 0.12f},
              {0.01f, -0.7f, 0.2f, 0.12f},
              {-0.5f, -0.55f, 0.3f, 0.12f}},
             {0.2f, 0.7f, 0.65f, 0.45f});
    polyline({{-0.7f, 0.5f, -0.3f, 0.1f},
              {-0.01f, 0.6f, -0.2f, 0.1f},
              {0.0f, 0.45f, -0.35f, 0.1f},
              {0.7f, 0.55f, -0.3f, 0.1f}},
             {0.3f, 0.4f, 0.9f, 0.45f});
    return l;
}

TEST(RaytracedRegions, regions_meeting_at_a_face_compose_eye_inside_and_joints_on_the_face) {
    const StyledLines lines = faceLines();
    const RegionSplit split = RegionSplit::split(0, 0.0f, RegionSplit::leaf(), RegionSplit::leaf());
    EXPECT_EQ(test::segmentsCrossingRegions(lines, split.boxes()), 8u);
    const int w = 80, h = 60;
    for (const Camera& cam : {camera({0.4f, 0.9f, 2.6f}), camera({0.02f, 0.0f, 0.02f}, {0.15f, 1.0f, 0.2f})}) {
        const bool inside = cam.eye.z < 0.1f;
        const char* view = inside ? "eye inside the tube" : "outside";
        const Scene opaque = raytracedScene(Transparency::Opaque);
        const FrameImages full = trace(opaque, lines, cam, w, h);
        const std::vector<FrameImages> regions = traceRegions(opaque, lines, cam, w, h, split, Share::Reaching);
        for (std::size_t r = 0; r < 2; ++r)
            EXPECT_EQ(test::pixelsOutsideBox(regions[r], cam, split.boxes()[r]), 0u) << view;
        EXPECT_GT(covered(regions[0]), 100u) << view;
        EXPECT_GT(covered(regions[1]), 100u) << view;
        EXPECT_EQ(differingPixels(compositeNearest(regions), full), 0u) << view;
        for (bool capClipping : {true, false}) {
            const Scene transparent = raytracedScene(Transparency::DepthPeeling, capClipping);
            const FrameImages fullT = trace(transparent, lines, cam, w, h);
            const FrameImages composite = compositeUnder(
                traceRegions(transparent, lines, cam, w, h, split, Share::Reaching), split.frontToBack(cam));
            double maxAlpha = 0;
            for (std::size_t i = 0; i < full.pixelCount(); ++i)
                maxAlpha = std::max(maxAlpha, double(std::abs(composite.rgba[4 * i + 3] - fullT.rgba[4 * i + 3])));
            const double psnr = compareRgba(composite.rgba, fullT.rgba).psnr;
            std::printf("[ measured ] raytraced face scene, %s, %s: PSNR %.1f dB, max |alpha diff| %.2e\n", view,
                        capClipping ? "joined" : "separate", psnr, maxAlpha);
            EXPECT_GE(psnr, kMinPsnr) << view;
            // A doubled or lost entry at a joint on the face moves alpha by >= 0.05 here.
            EXPECT_LT(maxAlpha, 1e-5) << view;
        }
    }
}

// AO by cone tracing: each region deposits the segments whose first vertex is in its box into the
// grid of the whole data's bounds; reduceDensity hands every region the sum of all regions' grids.
TEST(RaytracedRegions, cone_traced_ao_with_summed_density_matches_the_full_frame) {
    const StyledLines lines = randomLines(23, 30, 1.0f, 1.0f);
    const int w = 64, h = 48;
    const Camera cam = camera({-1.4f, 1.5f, 2.0f});
    Scene scene = raytracedScene(Transparency::Opaque);
    scene.render.ao.enabled = true;
    scene.render.ao.resolution = 40;
    const FrameImages full = trace(scene, lines, cam, w, h);
    for (const Layout& layout : layouts()) {
        const std::vector<RegionBox> boxes = layout.split.boxes();
        std::vector<StyledLines> parts;
        for (const RegionBox& b : boxes) parts.push_back(linesReaching(lines, b));
        std::vector<float> sum;
        for (std::size_t r = 0; r < boxes.size(); ++r) {
            const DensityGrid own =
                buildLineDensity(parts[r], scene.render.ao.resolution, {boxes[r], lines.bounds, 0.0f, nullptr});
            // Without a reduction a rank keeps its whole share; with one, only what it owns.
            RegionSetup owning{boxes[r], lines.bounds, 0.0f, [&sum](std::vector<float>& g) {
                                   if (sum.empty()) sum.assign(g.size(), 0.0f);
                                   for (std::size_t v = 0; v < g.size(); ++v) sum[v] += g[v];
                               }};
            const DensityGrid owned = buildLineDensity(parts[r], scene.render.ao.resolution, owning);
            EXPECT_GE(own.total(), owned.total());
        }
        std::vector<FrameImages> regions;
        for (std::size_t r = 0; r < boxes.size(); ++r) {
            TechniqueHooks hooks;
            hooks.reduceDensity = [&sum](std::vector<float>& g) { g = sum; };
            regions.push_back(trace(scene, parts[r], cam, w, h, boxes[r], &lines, hooks));
        }
        float maxRgba = 0, maxAo = 0;
        const std::size_t d = differingPixels(compositeNearest(regions), full, &maxRgba, &maxAo);
        std::printf("[ measured ] raytraced cone-traced AO, %s: %zu px differ, max |rgba| %.2e, max |ao| %.2e\n",
                    layout.name, d, maxRgba, maxAo);
        EXPECT_LE(maxAo, 1e-5f) << layout.name;
        EXPECT_LE(maxRgba, 1e-5f) << layout.name;
    }
}

// The density owner rule: summed over regions, the owned grids are the full grid (each segment
// deposits on exactly one rank, even when several hold it), to float rounding of the sum.
TEST(RaytracedRegions, owned_density_grids_sum_to_the_full_grid) {
    const StyledLines lines = randomLines(24, 40, 0.3f, 1.0f);
    const DensityGrid full = buildLineDensity(lines, 48, {});
    for (const Layout& layout : layouts()) {
        std::vector<double> sum(full.density.size(), 0.0);
        for (const RegionBox& box : layout.split.boxes()) {
            const DensityGrid owned =
                buildLineDensity(linesReaching(lines, box), 48, {box, lines.bounds, 0.0f, [](std::vector<float>&) {}});
            ASSERT_EQ(owned.size, full.size);
            ASSERT_EQ(owned.origin, full.origin);
            for (std::size_t v = 0; v < sum.size(); ++v) sum[v] += owned.density[v];
        }
        double maxDiff = 0;
        for (std::size_t v = 0; v < sum.size(); ++v)
            maxDiff =
                std::max(maxDiff, std::abs(sum[v] - double(full.density[v])) / std::max(1.0, double(full.density[v])));
        std::printf("[ measured ] owned density grids, %s: max relative difference %.2e\n", layout.name, maxDiff);
        EXPECT_LT(maxDiff, 1e-6) << layout.name;
    }
}

TEST(RaytracedRegions, ray_traced_ao_refuses_a_region) {
    const StyledLines lines = randomLines(25, 4, 1.0f, 1.0f);
    Scene scene = raytracedScene(Transparency::Opaque);
    scene.render.ao.enabled = true;
    scene.render.ao.method = AoSpec::Method::RayTraced;
    RegionBox half;
    half.lo.y = 0.0f;
    try {
        trace(scene, lines, camera({0, 0, 3}), 8, 8, half, &lines);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "scene.json: render.ao.method: \"ray_traced\" does not support data-parallel "
                  "rendering (--mpi); supported: \"cone_traced\"");
    }
    EXPECT_NO_THROW(trace(scene, lines, camera({0, 0, 3}), 8, 8));
}

// --- Particles -------------------------------------------------------------------------------

// Disjoint spheres (the transparent mode is exact for them): 120 spheres, radii 0.05..0.2.
StyledParticles randomSpheres(unsigned seed, int count) {
    std::mt19937 rng(seed);
    auto u = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) * (1.0f / 16777216.0f); };
    StyledParticles s;
    while (int(s.size()) < count) {
        const glm::vec4 c(u(-0.8f, 0.8f), u(-0.8f, 0.8f), u(-0.8f, 0.8f), u(0.05f, 0.2f));
        bool overlaps = false;
        for (const glm::vec4& o : s.centerRadius)
            overlaps = overlaps || glm::distance(glm::vec3(c), glm::vec3(o)) < c.w + o.w;
        if (overlaps) continue;
        s.centerRadius.push_back(c);
        s.color.emplace_back(u(0.05f, 1.0f), u(0.05f, 1.0f), u(0.05f, 1.0f), u(0.3f, 0.9f));
        s.id.push_back(std::uint32_t(s.size()));
        s.bounds.extend(glm::vec3(c), c.w);
        s.maxRadius = std::max(s.maxRadius, c.w);
    }
    return s;
}

FrameImages traceSpheres(const Scene& scene, const StyledParticles& p, const Camera& cam, int w, int h,
                         const RegionSetup& region = {}) {
    auto r = rt::RaytracedParticles::create(scene, p, region);
    FrameImages img;
    CpuStageTimer timer;
    r->render(cam, w, h, img, timer);
    return img;
}

// Opaque and transparent, with and without cone-traced AO (volumes summed over the regions), and
// the eye inside a sphere that the split plane cuts.
TEST(RaytracedRegions, sphere_regions_composite_to_the_full_frame) {
    StyledParticles spheres = randomSpheres(31, 120);
    const int w = 72, h = 54;
    struct View {
        const char* name;
        Camera cam;
    };
    const glm::vec3 inside = glm::vec3(spheres.centerRadius[0]) + glm::vec3(0.3f * spheres.centerRadius[0].w);
    const View views[] = {{"outside", camera({1.8f, 1.1f, 2.5f})}, {"eye inside a sphere", camera(inside, {0, 0, 0})}};
    for (const View& v : views) {
        // The first layout's plane goes through the eye's sphere when the eye is inside one.
        std::vector<Layout> splits = layouts();
        if (&v != &views[0])
            splits[0].split =
                RegionSplit::split(0, spheres.centerRadius[0].x, RegionSplit::leaf(), RegionSplit::leaf());
        for (const Layout& layout : splits) {
            const std::vector<RegionBox> boxes = layout.split.boxes();
            for (Transparency mode : {Transparency::Opaque, Transparency::DepthPeeling}) {
                for (bool ao : {false, true}) {
                    Scene scene = raytracedScene(mode);
                    scene.render.ao.enabled = ao;
                    scene.render.ao.resolution = 32;
                    const std::string label = std::string(v.name) + ", " + layout.name +
                                              (mode == Transparency::Opaque ? ", opaque" : ", transparent") +
                                              (ao ? ", AO" : "");
                    const FrameImages full = traceSpheres(scene, spheres, v.cam, w, h);
                    std::vector<StyledParticles> parts;
                    for (const RegionBox& b : boxes) parts.push_back(spheresReaching(spheres, b));
                    std::vector<float> sum;
                    if (ao)
                        for (std::size_t r = 0; r < boxes.size(); ++r)
                            rt::SphereVolume(
                                scene.render.ao, parts[r],
                                {boxes[r], spheres.bounds, spheres.maxRadius, [&sum](std::vector<float>& g) {
                                     if (sum.empty()) sum.assign(g.size(), 0.0f);
                                     for (std::size_t k = 0; k < g.size(); ++k) sum[k] += g[k];
                                 }});
                    std::vector<FrameImages> regions;
                    for (std::size_t r = 0; r < boxes.size(); ++r) {
                        RegionSetup setup{boxes[r], spheres.bounds, spheres.maxRadius, nullptr};
                        if (ao) setup.reduceDensity = [&sum](std::vector<float>& g) { g = sum; };
                        regions.push_back(traceSpheres(scene, parts[r], v.cam, w, h, setup));
                    }
                    if (mode == Transparency::Opaque) {
                        float maxRgba = 0, maxAo = 0;
                        const std::size_t d = differingPixels(compositeNearest(regions), full, &maxRgba, &maxAo);
                        std::printf("[ measured ] raytraced spheres, %s: %zu px differ (max |rgba| %.2e, |ao| %.2e)\n",
                                    label.c_str(), d, maxRgba, maxAo);
                        if (ao) {
                            EXPECT_LE(maxRgba, 1e-5f) << label;
                            EXPECT_LE(maxAo, 1e-5f) << label;
                        } else {
                            EXPECT_EQ(d, 0u) << label;
                        }
                    } else {
                        const FrameImages composite = compositeUnder(regions, layout.split.frontToBack(v.cam));
                        const ImageMetrics m = compareRgba(composite.rgba, full.rgba);
                        std::printf("[ measured ] raytraced spheres, %s: PSNR %.1f dB, max |diff| %.2e\n",
                                    label.c_str(), m.psnr, m.maxError);
                        EXPECT_GE(m.psnr, kMinPsnr) << label;
                        EXPECT_EQ(composite.depth, full.depth) << label;
                        EXPECT_EQ(composite.id, full.id) << label;
                    }
                }
            }
        }
    }
}

}  // namespace
}  // namespace tc
