// Data-parallel rendering without MPI: a scene split by hand-made k-d planes into 2, 3 and 4 region
// boxes (core/region.h), each region rendered by its own technique on the share of the data a rank
// would hold (tests/region_split.h: the segments that reach the box, with their polyline
// neighbours) or on all of it, and the regions composited on the CPU as IceT does over ranks:
// opaque frames by depth (Z), transparent ones "under" in the regions' view order. The composite
// must be the single full render: every contribution to a pixel (a tube's or sphere's entry
// point) belongs to exactly one region.
//
// Agreement asked for: opaque composites bit-identical to the full frame (rgba, depth, normal,
// id): the region's fragments are the full frame's fragments, shaded by the same program on the
// same inputs, and the depth test picks the same one. Transparent composites PSNR >= 50 dB
// against the full depth-peeled frame: the "under" sums associate differently (per region, then
// across regions), which moves a channel by float ulps (~1e-7); a lost or doubled fragment moves
// it by its alpha times its colour, >= 1e-2 here. The k-buffer adds the RGBA8 rounding of its
// stored fragments (0.5 / 255 per channel).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image_metrics.h"
#include "core/scene.h"
#include "core/technique.h"
#include "core/voxel_density.h"
#include "gl/gpu_timer.h"
#include "gl/sphere_renderer.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "region_split.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

constexpr double kMinPsnr = 50.0;

// --- Scenes and splits -----------------------------------------------------------------------

// 64 random bent polylines (4..10 segments of 0.15..0.45, radii 0.04..0.1) in [-0.6, 0.6]^3:
// dense enough that the split planes near the centre cut many tubes.
StyledLines denseScene(std::uint32_t seed, float alphaLo = 1.0f, float alphaHi = 1.0f, int polylines = 64) {
    RandomSceneOptions o;
    o.polylines = polylines;
    o.minSegments = 4;
    o.maxSegments = 10;
    o.radiusMin = 0.04f;
    o.radiusRatio = 2.5f;
    o.extent = 0.6f;
    StyledLines lines = randomLineScene(seed, o);
    for (std::size_t v = 0; v < lines.color.size(); ++v)
        lines.color[v].w = alphaLo + (alphaHi - alphaLo) * float((v * 7919u) % 101u) / 100.0f;
    return lines;
}

// --- Rendering -------------------------------------------------------------------------------

Scene linesScene(Transparency mode, int w, int h, bool aovs = true) {
    Scene scene;
    scene.image.width = w;
    scene.image.height = h;
    scene.render.transparency = mode;
    scene.render.kbufferK = 16;
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = aovs;
    return scene;
}

FrameImages renderTechnique(Technique& technique, const Camera& cam, int w, int h) {
    gl::StageTimer timer;
    FrameImages out;
    technique.render(FrameSetup{0, cam, w, h}, out, timer);
    timer.collect();
    return out;
}

// One technique for `lines` drawing `box` of a dataset whose bounds (every rank's) are `bounds`.
// Every rank gets the bounds and the largest radius of the whole dataset (`all`).
FrameImages renderRegion(const Scene& scene, const StyledLines& lines, const Camera& cam, int w, int h,
                         const RegionBox& box, const StyledLines& all, const TechniqueHooks& hooks = {}) {
    TechniqueData data;
    data.lines = &lines;
    data.region = box;
    data.bounds = all.bounds;
    data.maxRadius = all.maxRadius;
    return renderTechnique(*gl::createTechnique(scene, data, hooks), cam, w, h);
}

FrameImages renderFull(const Scene& scene, const StyledLines& lines, const Camera& cam, int w, int h) {
    return renderTechnique(*gl::createTechnique(scene, lines), cam, w, h);
}

enum class Share { Reaching, All };

std::vector<FrameImages> renderRegions(const Scene& scene, const StyledLines& lines, const Camera& cam, int w, int h,
                                       const RegionSplit& split, Share share) {
    std::vector<FrameImages> out;
    for (const RegionBox& box : split.boxes()) {
        const StyledLines part = share == Share::All ? lines : linesReaching(lines, box);
        out.push_back(renderRegion(scene, part, cam, w, h, box, lines));
    }
    return out;
}

// --- Comparison ------------------------------------------------------------------------------

std::size_t coveredPixels(const FrameImages& f) {
    std::size_t n = 0;
    for (std::uint32_t id : f.id) n += id != kBackgroundId;
    return n;
}

// Pixels whose values differ in any bit, per buffer.
struct BitDiff {
    std::size_t rgba = 0, depth = 0, normal = 0, id = 0, ao = 0;
    float maxRgba = 0, maxAo = 0;
    std::size_t total() const { return rgba + depth + normal + id + ao; }
};

BitDiff bitDiff(const FrameImages& a, const FrameImages& b) {
    BitDiff d;
    auto differs = [](const float* x, const float* y, int n) { return std::memcmp(x, y, sizeof(float) * n) != 0; };
    for (std::size_t i = 0; i < a.pixelCount(); ++i) {
        if (differs(&a.rgba[4 * i], &b.rgba[4 * i], 4)) {
            ++d.rgba;
            for (int c = 0; c < 4; ++c)
                d.maxRgba = std::max(d.maxRgba, std::abs(a.rgba[4 * i + c] - b.rgba[4 * i + c]));
        }
        d.depth += differs(&a.depth[i], &b.depth[i], 1);
        d.normal += differs(&a.normal[3 * i], &b.normal[3 * i], 3);
        d.id += a.id[i] != b.id[i];
        if (!a.ao.empty() && differs(&a.ao[i], &b.ao[i], 1)) {
            ++d.ao;
            d.maxAo = std::max(d.maxAo, std::abs(a.ao[i] - b.ao[i]));
        }
    }
    return d;
}

// The AOVs of transparent frames (first surface): Z-composited, so equal to the full frame's.
void expectSameAovs(const FrameImages& composite, const FrameImages& full, const std::string& label) {
    EXPECT_EQ(composite.depth, full.depth) << label;
    EXPECT_EQ(composite.normal, full.normal) << label;
    EXPECT_EQ(composite.id, full.id) << label;
}

// ---------------------------------------------------------------------------------------------

// Opaque rounded cones (G-buffer visibility and attributes passes, deferred shading): every
// split, both shares of the data. Seed 3's scene has 463 segments; the planes cut 75 (2
// regions), 109 (3) and 145 (4) of them (segments whose tube reaches more than one region,
// asserted below). Each region's image must also show nothing outside its box (Z compositing
// alone would hide a region that draws too much).
TEST_F(GlTest, opaque_regions_z_composite_bit_identically_to_the_full_frame) {
    const int w = 112, h = 84;
    const StyledLines lines = denseScene(3);
    const Camera cam = lookAt({1.7f, 1.1f, 2.3f});
    const Scene scene = linesScene(Transparency::Opaque, w, h);
    const FrameImages full = renderFull(scene, lines, cam, w, h);
    ASSERT_GT(coveredPixels(full), std::size_t(w * h / 3));
    ASSERT_EQ(lines.segmentCount(), 463u);
    const std::size_t expectedCrossing[] = {75, 109, 145};
    int l = 0;
    for (const Layout& layout : layouts()) {
        const std::size_t crossing = segmentsCrossingRegions(lines, layout.split.boxes());
        EXPECT_EQ(crossing, expectedCrossing[l++]) << layout.name;
        for (Share share : {Share::Reaching, Share::All}) {
            const std::string label =
                std::string(layout.name) + (share == Share::All ? ", all segments" : ", reaching segments");
            const std::vector<FrameImages> regions = renderRegions(scene, lines, cam, w, h, layout.split, share);
            const std::vector<RegionBox> boxes = layout.split.boxes();
            std::size_t covered = 0;
            for (std::size_t r = 0; r < regions.size(); ++r) {
                EXPECT_GT(coveredPixels(regions[r]), 100u) << label << ": a region drew (almost) nothing";
                // Z compositing would hide a region drawing too much; its own image does not.
                EXPECT_EQ(pixelsOutsideBox(regions[r], cam, boxes[r]), 0u) << label << ", region " << r;
                covered += coveredPixels(regions[r]);
            }
            const BitDiff d = bitDiff(compositeNearest(regions), full);
            std::printf(
                "[ measured ] opaque, %s (%zu of %zu segments cross): %zu differing pixels (rgba %zu, depth %zu, "
                "normal %zu, id %zu); region coverage %zu px for %zu px of the frame\n",
                label.c_str(), crossing, lines.segmentCount(), d.total(), d.rgba, d.depth, d.normal, d.id, covered,
                coveredPixels(full));
            EXPECT_EQ(d.total(), 0u) << label;
        }
    }
}

// Transparent tubes with cap clipping: depth peeling per region (exact) and the k-buffer (k = 16,
// above this scene's depth complexity), composited "under" in view order, against the full
// depth-peeled frame; the first-surface AOVs Z-composite exactly. Seed 5, alpha 0.25..0.65; a
// perspective view and an orthographic one (view order by direction, not by eye position).
TEST_F(GlTest, transparent_regions_composited_in_view_order_match_the_full_depth_peeled_frame) {
    const int w = 96, h = 72;
    const StyledLines lines = denseScene(5, 0.25f, 0.65f);
    Camera ortho = lookAt({-1.6f, 0.9f, -2.2f});
    ortho.projection = Projection::Orthographic;
    ortho.orthoHeight = 2.2f;
    for (const Camera& cam : {lookAt({1.8f, -1.2f, 2.1f}), ortho}) {
        const char* view = cam.projection == Projection::Orthographic ? "orthographic" : "perspective";
        const FrameImages full = renderFull(linesScene(Transparency::DepthPeeling, w, h), lines, cam, w, h);
        for (const Layout& layout : layouts()) {
            const std::vector<std::size_t> order = layout.split.frontToBack(cam);
            for (Transparency mode : {Transparency::DepthPeeling, Transparency::KBuffer}) {
                const std::string label = std::string(view) + ", " + layout.name +
                                          (mode == Transparency::KBuffer ? ", k-buffer k=16" : ", depth peeling");
                const std::vector<FrameImages> regions =
                    renderRegions(linesScene(mode, w, h), lines, cam, w, h, layout.split, Share::Reaching);
                for (std::size_t r = 0; r < regions.size(); ++r)
                    EXPECT_EQ(pixelsOutsideBox(regions[r], cam, layout.split.boxes()[r]), 0u)
                        << label << ", region " << r;
                const FrameImages composite = compositeUnder(regions, order);
                const ImageMetrics m = compareRgba(composite.rgba, full.rgba);
                std::printf("[ measured ] transparent, %s: PSNR %.1f dB, max |diff| %.2e\n", label.c_str(), m.psnr,
                            m.maxError);
                EXPECT_GE(m.psnr, kMinPsnr) << label;
                expectSameAovs(composite, full, label);
            }
        }
    }
}

// The order matters and is the one RegionSplit::frontToBack gives: a red layer of tubes in region
// z < 0 and a blue one in z >= 0, both alpha 0.7, seen from +z and from -z. Composited front to
// back the regions give the full frame; in the reverse order the front layer's colour is the
// wrong one (PSNR far below 50 dB, and the dominant channel at the centre flips).
TEST_F(GlTest, transparent_regions_composited_in_the_wrong_order_visibly_differ) {
    std::vector<TestPolyline> polylines;
    for (int i = 0; i < 9; ++i) {
        const float y = -0.8f + 0.2f * float(i);
        const glm::vec4 red(0.9f, 0.1f, 0.1f, 0.7f), blue(0.1f, 0.1f, 0.9f, 0.7f);
        polylines.push_back(
            {{{-0.9f, y, -0.3f}, 0.12f, red}, {{0.0f, y + 0.02f, -0.3f}, 0.12f, red}, {{0.9f, y, -0.3f}, 0.12f, red}});
        polylines.push_back(
            {{{y, -0.9f, 0.3f}, 0.12f, blue}, {{y + 0.02f, 0.0f, 0.3f}, 0.12f, blue}, {{y, 0.9f, 0.3f}, 0.12f, blue}});
    }
    const StyledLines lines = makeStyledLines(polylines);
    const RegionSplit split = RegionSplit::split(2, 0.0f, RegionSplit::leaf(), RegionSplit::leaf());
    const int w = 80, h = 80;
    for (float side : {1.0f, -1.0f}) {
        const Camera cam = lookAt({0.1f, 0.15f, 3.0f * side});
        const Scene scene = linesScene(Transparency::DepthPeeling, w, h);
        const FrameImages full = renderFull(scene, lines, cam, w, h);
        const std::vector<FrameImages> regions = renderRegions(scene, lines, cam, w, h, split, Share::Reaching);
        std::vector<std::size_t> order = split.frontToBack(cam);
        ASSERT_EQ(order.size(), 2u);
        EXPECT_EQ(order[0], side > 0 ? 1u : 0u) << "the eye's side of the plane comes first";
        const FrameImages right = compositeUnder(regions, order);
        std::reverse(order.begin(), order.end());
        const FrameImages wrong = compositeUnder(regions, order);
        const double good = compareRgba(right.rgba, full.rgba).psnr, bad = compareRgba(wrong.rgba, full.rgba).psnr;
        std::printf("[ measured ] layers seen from %s: view order %.1f dB, reversed %.1f dB\n", side > 0 ? "+z" : "-z",
                    good, bad);
        EXPECT_GE(good, kMinPsnr);
        EXPECT_LT(bad, 30.0);
        // The centre pixel shows two overlapping layers: the front one's colour dominates.
        const std::size_t c = 4 * (std::size_t(h / 2) * w + w / 2);
        const bool redInFront = side < 0;
        EXPECT_EQ(full.rgba[c] > full.rgba[c + 2], redInFront);
        EXPECT_EQ(right.rgba[c] > right.rgba[c + 2], redInFront);
        EXPECT_NE(wrong.rgba[c] > wrong.rgba[c + 2], redInFront);
    }
}

// Edge cases, each across the plane x = 0 of two regions:
// - a tube crossing the face: per pixel exactly one region shows it (its entry point's);
// - the eye inside a tube that crosses the face (the visible inner wall lies in either region);
// - cap clipping at joints on and next to the face, whose two segments lie in different regions:
//   the transparent tube is entered once, so no bead (doubled entry) and no hole appear in the
//   composite where the regions meet.
StyledLines faceScene() {
    const glm::vec4 orange(0.85f, 0.5f, 0.2f, 0.45f), teal(0.2f, 0.7f, 0.65f, 0.45f);
    std::vector<TestPolyline> polylines;
    // A thick straight tube along x through the face, radius 0.25 (the eye goes inside it).
    polylines.push_back({{{-1.2f, 0.0f, 0.0f}, 0.25f, orange}, {{1.2f, 0.05f, 0.0f}, 0.25f, orange}});
    // A zig-zag with joints exactly on the face (x = 0) and 0.01 beside it.
    polylines.push_back({{{-0.6f, -0.5f, 0.3f}, 0.12f, teal},
                         {{0.0f, -0.35f, 0.25f}, 0.12f, teal},
                         {{0.45f, -0.5f, 0.35f}, 0.12f, teal},
                         {{0.01f, -0.7f, 0.2f}, 0.12f, teal},
                         {{-0.5f, -0.55f, 0.3f}, 0.12f, teal}});
    polylines.push_back({{{-0.7f, 0.5f, -0.3f}, 0.1f, orange},
                         {{-0.01f, 0.6f, -0.2f}, 0.1f, teal},
                         {{0.0f, 0.45f, -0.35f}, 0.1f, orange},
                         {{0.7f, 0.55f, -0.3f}, 0.1f, teal}});
    return makeStyledLines(polylines);
}

TEST_F(GlTest, regions_meeting_at_a_face_compose_tubes_crossing_it_eye_inside_and_clipped_joints) {
    const StyledLines lines = faceScene();
    const RegionSplit split = RegionSplit::split(0, 0.0f, RegionSplit::leaf(), RegionSplit::leaf());
    ASSERT_EQ(segmentsCrossingRegions(lines, split.boxes()), 8u);
    const int w = 96, h = 72;
    struct View {
        const char* name;
        Camera cam;
    };
    const View views[] = {{"outside", lookAt({0.4f, 0.9f, 2.6f})},
                          {"eye inside the tube", lookAt({0.02f, 0.0f, 0.02f}, {0.15f, 1.0f, 0.2f})}};
    for (const View& v : views) {
        const Scene opaque = linesScene(Transparency::Opaque, w, h);
        const FrameImages full = renderFull(opaque, lines, v.cam, w, h);
        const std::vector<FrameImages> regions = renderRegions(opaque, lines, v.cam, w, h, split, Share::Reaching);
        for (std::size_t r = 0; r < 2; ++r)
            EXPECT_EQ(pixelsOutsideBox(regions[r], v.cam, split.boxes()[r]), 0u) << v.name;
        const BitDiff d = bitDiff(compositeNearest(regions), full);
        std::printf("[ measured ] face scene, %s, opaque: %zu differing pixels\n", v.name, d.total());
        EXPECT_EQ(d.total(), 0u) << v.name;
        // Each region shows part of the frame, and together they cover all of it.
        std::size_t both = 0, onlyLeft = 0, onlyRight = 0;
        for (std::size_t i = 0; i < full.pixelCount(); ++i) {
            const bool a = regions[0].id[i] != kBackgroundId, b = regions[1].id[i] != kBackgroundId;
            both += a && b;
            onlyLeft += a && !b;
            onlyRight += b && !a;
        }
        EXPECT_GT(onlyLeft, 200u) << v.name;
        EXPECT_GT(onlyRight, 200u) << v.name;

        const Scene transparent = linesScene(Transparency::DepthPeeling, w, h);
        const FrameImages fullT = renderFull(transparent, lines, v.cam, w, h);
        const std::vector<FrameImages> regionsT =
            renderRegions(transparent, lines, v.cam, w, h, split, Share::Reaching);
        const FrameImages composite = compositeUnder(regionsT, split.frontToBack(v.cam));
        const ImageMetrics m = compareRgba(composite.rgba, fullT.rgba);
        double maxAlpha = 0;
        for (std::size_t i = 0; i < composite.pixelCount(); ++i)
            maxAlpha = std::max(maxAlpha, double(std::abs(composite.rgba[4 * i + 3] - fullT.rgba[4 * i + 3])));
        std::printf("[ measured ] face scene, %s, depth peeling: PSNR %.1f dB, max |alpha diff| %.2e\n", v.name, m.psnr,
                    maxAlpha);
        EXPECT_GE(m.psnr, kMinPsnr) << v.name;
        // A doubled or lost entry at a joint moves alpha by (1 - A) 0.45 >= 0.05 here.
        EXPECT_LT(maxAlpha, 1e-5) << v.name;
        expectSameAovs(composite, fullT, v.name);
    }
}

// Ambient occlusion: every region voxelizes the segments it owns (first vertex in its box) into
// the grid of the whole dataset's bounds, reduceDensity sums the regions' grids (done here in two
// passes: record each grid, then hand every region the sum), and the composite's ao AOV and colour
// match the full render's. The line cache is per segment, so the "all segments" share is used with
// it; the exact tracer ("none") with the reaching share.
TEST_F(GlTest, opaque_ao_of_regions_with_summed_density_matches_the_full_frame) {
    const int w = 96, h = 72;
    const StyledLines lines = denseScene(7);
    const Camera cam = lookAt({-1.5f, 1.4f, 2.2f});
    for (AoSpec::Cache cache : {AoSpec::Cache::Precomputed, AoSpec::Cache::None}) {
        Scene scene = linesScene(Transparency::Opaque, w, h);
        scene.render.ao.enabled = true;
        scene.render.ao.resolution = 48;
        scene.render.ao.cache = cache;
        scene.output.aovAo = true;
        const FrameImages full = renderFull(scene, lines, cam, w, h);
        const Share share = cache == AoSpec::Cache::Precomputed ? Share::All : Share::Reaching;
        for (const Layout& layout : layouts()) {
            const std::string label =
                std::string(layout.name) + (cache == AoSpec::Cache::Precomputed ? ", cached AO" : ", traced AO");
            const std::vector<RegionBox> boxes = layout.split.boxes();
            std::vector<StyledLines> parts;
            for (const RegionBox& box : boxes) parts.push_back(share == Share::All ? lines : linesReaching(lines, box));
            // Pass 1: each region's own grid (as a rank builds it before the reduction).
            std::vector<float> sum;
            for (std::size_t r = 0; r < boxes.size(); ++r) {
                std::vector<float> own;
                RegionSetup setup{boxes[r], lines.bounds, lines.maxRadius, [&own](std::vector<float>& g) { own = g; }};
                buildLineDensity(parts[r], scene.render.ao.resolution, setup);
                if (sum.empty()) sum.assign(own.size(), 0.0f);
                ASSERT_EQ(own.size(), sum.size()) << label << ": the regions' grids differ in size";
                for (std::size_t v = 0; v < own.size(); ++v) sum[v] += own[v];
            }
            // Pass 2: the techniques, with the reduction handing them the sum.
            std::vector<FrameImages> regions;
            for (std::size_t r = 0; r < boxes.size(); ++r) {
                TechniqueHooks hooks;
                std::size_t calls = 0;
                hooks.reduceDensity = [&](std::vector<float>& g) {
                    ++calls;
                    ASSERT_EQ(g.size(), sum.size());
                    g = sum;
                };
                regions.push_back(renderRegion(scene, parts[r], cam, w, h, boxes[r], lines, hooks));
                EXPECT_EQ(calls, 1u) << label;
            }
            const BitDiff d = bitDiff(compositeNearest(regions), full);
            std::printf(
                "[ measured ] opaque AO, %s: %zu px differ in ao (max %.2e), %zu in rgba (max %.2e), "
                "%zu in depth/normal/id\n",
                label.c_str(), d.ao, d.maxAo, d.rgba, d.maxRgba, d.depth + d.normal + d.id);
            // The float sum of the ranks' grids differs from the one-process grid by ulps where
            // two regions deposit into one voxel, so AO may differ by about that much.
            EXPECT_LE(d.maxAo, 1e-5f) << label;
            EXPECT_LE(d.maxRgba, 1e-5f) << label;
            EXPECT_EQ(d.depth + d.normal + d.id, 0u) << label;
        }
    }
}

// Sphere glyphs (gl/sphere_renderer.h): disjoint spheres, so the power-distance order of the
// transparent mode is the exact per-ray order and a region's spheres blend exactly as in the full
// frame, with one chunk. With the default early-z chunks (Sect. 5.2 of Staib et al.) a pixel skips
// later chunks once its alpha exceeds the threshold, and a region cannot know the alpha of the
// regions in front: the composite then differs by at most 1 - threshold (the approximation's own
// bound), which is asserted too. 150 spheres with radii 0.06..0.25; the split planes cut 16, 30
// and 33 of them (asserted).
StyledParticles disjointSpheres(int count) {
    StyledParticles p;
    std::uint32_t state = 12345u;
    auto u = [&](float lo, float hi) {
        state = state * 1664525u + 1013904223u;
        return lo + (hi - lo) * float(state >> 8) * (1.0f / 16777216.0f);
    };
    int attempts = 0;
    while (int(p.size()) < count && ++attempts < 100000) {
        const glm::vec3 c(u(-0.9f, 0.9f), u(-0.9f, 0.9f), u(-0.9f, 0.9f));
        const float r = u(0.06f, 0.25f);
        bool ok = true;
        for (const glm::vec4& q : p.centerRadius) ok = ok && glm::distance(c, glm::vec3(q)) > r + q.w + 0.01f;
        if (!ok) continue;
        p.centerRadius.emplace_back(c, r);
        p.color.emplace_back(u(0.1f, 1.0f), u(0.1f, 1.0f), u(0.1f, 1.0f), u(0.4f, 0.9f));
        p.id.push_back(std::uint32_t(p.id.size()));
        p.bounds.extend(c, r);
        p.maxRadius = std::max(p.maxRadius, r);
    }
    return p;
}

std::size_t spheresCrossing(const StyledParticles& p, const std::vector<RegionBox>& boxes) {
    std::size_t n = 0;
    for (const glm::vec4& cr : p.centerRadius) {
        std::size_t reached = 0;
        for (const RegionBox& b : boxes) reached += b.reaches(glm::vec3(cr) - cr.w, glm::vec3(cr) + cr.w);
        n += reached > 1;
    }
    return n;
}

TEST_F(GlTest, sphere_regions_composite_to_the_full_frame_with_ao_from_summed_volumes) {
    const int w = 96, h = 72;
    const StyledParticles spheres = disjointSpheres(150);
    ASSERT_EQ(spheres.size(), 150u);
    const Camera cam = lookAt({1.9f, 1.0f, 2.6f});
    const std::size_t expectedCrossing[] = {16, 30, 33};
    int l = 0;
    for (const Layout& layout : layouts()) {
        const std::vector<RegionBox> boxes = layout.split.boxes();
        EXPECT_EQ(spheresCrossing(spheres, boxes), expectedCrossing[l++]) << layout.name;
        struct Mode {
            Transparency transparency;
            int chunks;
        };
        for (const Mode mode : {Mode{Transparency::Opaque, 1}, Mode{Transparency::ObjectOrder, 1},
                                Mode{Transparency::ObjectOrder, SpheresSpec{}.chunks}}) {
            for (bool ao : {false, true}) {
                Scene scene = linesScene(mode.transparency, w, h);
                scene.render.technique = RenderTechnique::Spheres;
                scene.render.spheres.chunks = mode.chunks;
                scene.render.ao.enabled = ao;
                scene.render.ao.resolution = 40;
                scene.output.aovAo = ao;
                const std::string label = std::string(layout.name) +
                                          (mode.transparency == Transparency::Opaque ? ", opaque" : ", transparent") +
                                          (mode.chunks > 1 ? ", early-z chunks" : "") + (ao ? ", AO" : "");
                const FrameImages full = renderTechnique(*gl::SphereRenderer::create(scene, spheres), cam, w, h);
                std::vector<StyledParticles> parts;
                for (const RegionBox& box : boxes) parts.push_back(spheresReaching(spheres, box));
                // The sum of the regions' AO volumes: pass 1 records each one's level 0.
                std::vector<float> sum;
                if (ao)
                    for (std::size_t r = 0; r < boxes.size(); ++r) {
                        RegionSetup record{boxes[r], spheres.bounds, spheres.maxRadius, [&sum](std::vector<float>& g) {
                                               if (sum.empty()) sum.assign(g.size(), 0.0f);
                                               for (std::size_t v = 0; v < g.size(); ++v) sum[v] += g[v];
                                           }};
                        renderTechnique(*gl::SphereRenderer::create(scene, parts[r], record), cam, 8, 8);
                    }
                std::vector<FrameImages> regions;
                for (std::size_t r = 0; r < boxes.size(); ++r) {
                    RegionSetup setup{boxes[r], spheres.bounds, spheres.maxRadius, nullptr};
                    if (ao) setup.reduceDensity = [&sum](std::vector<float>& g) { g = sum; };
                    regions.push_back(renderTechnique(*gl::SphereRenderer::create(scene, parts[r], setup), cam, w, h));
                }
                if (mode.transparency == Transparency::Opaque) {
                    const BitDiff d = bitDiff(compositeNearest(regions), full);
                    std::printf("[ measured ] spheres, %s: %zu px differ (rgba max %.2e, ao max %.2e)\n", label.c_str(),
                                d.total(), d.maxRgba, d.maxAo);
                    if (ao) {
                        EXPECT_LE(d.maxRgba, 1e-5f) << label;
                        EXPECT_LE(d.maxAo, 1e-5f) << label;
                        EXPECT_EQ(d.depth + d.normal + d.id, 0u) << label;
                    } else {
                        EXPECT_EQ(d.total(), 0u) << label;
                    }
                } else {
                    const FrameImages composite = compositeUnder(regions, layout.split.frontToBack(cam));
                    const ImageMetrics m = compareRgba(composite.rgba, full.rgba);
                    std::printf("[ measured ] spheres, %s: PSNR %.1f dB, max |diff| %.2e\n", label.c_str(), m.psnr,
                                m.maxError);
                    if (mode.chunks > 1)
                        EXPECT_LE(m.maxError, 1.0 - scene.render.spheres.earlyZThreshold) << label;
                    else
                        EXPECT_GE(m.psnr, kMinPsnr) << label;
                    expectSameAovs(composite, full, label);
                }
            }
        }
    }
}

// The registry path: the spheres technique on a line dataset (one sphere per vertex) takes the
// region from TechniqueData like the line techniques.
TEST_F(GlTest, spheres_of_line_vertices_take_the_region_from_the_technique_data) {
    const int w = 80, h = 60;
    const StyledLines lines = denseScene(11);
    const Camera cam = lookAt({1.6f, -1.0f, 2.4f});
    Scene scene = linesScene(Transparency::Opaque, w, h);
    scene.render.technique = RenderTechnique::Spheres;
    const RegionSplit split = layouts()[1].split;
    const FrameImages full = renderFull(scene, lines, cam, w, h);
    const std::vector<FrameImages> regions = renderRegions(scene, lines, cam, w, h, split, Share::All);
    for (const FrameImages& r : regions) EXPECT_LT(coveredPixels(r), coveredPixels(full));
    EXPECT_EQ(bitDiff(compositeNearest(regions), full).total(), 0u);
}

// Techniques without region clipping refuse a region with the technique registry's message.
TEST_F(GlTest, techniques_without_region_clipping_refuse_a_region) {
    const StyledLines lines = denseScene(1);
    RegionBox half;
    half.hi.x = 0.0f;
    TechniqueData data;
    data.lines = &lines;
    data.region = half;
    Scene vrc;
    vrc.file = "scene.json";
    vrc.render.technique = RenderTechnique::VoxelRaycast;
    Scene opacity;
    opacity.file = "scene.json";
    opacity.render.transparency = Transparency::OpacityOptimization;
    const std::string supported =
        " does not support data-parallel rendering (--mpi); supported: rasterized (opaque, kbuffer, depth_peeling), "
        "raytraced, spheres";
    for (const auto& [scene, expected] :
         {std::pair{vrc, "scene.json: render.technique: voxel_raycast" + supported},
          std::pair{opacity, "scene.json: render.transparency: opacity_optimization" + supported}}) {
        try {
            gl::createTechnique(scene, data);
            ADD_FAILURE() << "no error for " << expected;
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()), expected);
        }
        // Without a region they are made as before.
        TechniqueData whole = data;
        whole.region = RegionBox{};
        EXPECT_NO_THROW(gl::createTechnique(scene, whole));
    }
}

}  // namespace
}  // namespace tc::test
