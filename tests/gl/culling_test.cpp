// Depth slices with hierarchical culling (Groß & Gumhold 2020, Sect. 4.3;
// gl/hierarchical_culling.h) against the unculled renderers:
// - opaque: culling only removes hidden work, so colour, depth, normal and id are the same with
//   and without it, bit for bit (depth ties included), on every billboard path, and on a dense
//   scene most segments are culled;
// - transparent: a pixel is culled only once the opacity already blended into it exceeds the
//   threshold T, and everything the k-buffer or object order would still add to it is blended
//   *under* that, weighted by its transmittance < 1 - T. So every channel changes by at most
//   1 - T against the unculled render (and, by the triangle inequality, moves at most that much
//   further from depth peeling);
// - slicing itself (threshold 1: nothing can be culled) leaves the k-buffer bit-identical.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <utility>

#include "core/frustum.h"
#include "core/scene.h"
#include "core/technique.h"
#include "gl/gpu_timer.h"
#include "gl/hierarchical_culling.h"
#include "gl/line_geometry.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

struct Rendered {
    FrameImages images;
    std::uint64_t culled = 0;
    std::uint64_t outsideView = 0;  // stage "frustum" of the last frame
    bool hadCullingStage = false;
    nlohmann::json description;
};

Rendered render(const Scene& scene, const StyledLines& lines, const std::vector<Camera>& cameras) {
    std::unique_ptr<tc::Technique> technique = gl::createTechnique(scene, lines);
    Rendered r;
    gl::StageTimer timer;
    for (std::size_t i = 0; i < cameras.size(); ++i) {
        r.images = FrameImages{};
        technique->render(tc::FrameSetup{int(i), cameras[i], scene.image.width, scene.image.height}, r.images, timer);
        r.culled = 0;
        r.outsideView = 0;
        for (const tc::StageTime& t : timer.collect()) {
            if (t.stage == "culling") {
                r.culled = t.items;
                r.hadCullingStage = true;
            }
            if (t.stage == "frustum") r.outsideView = t.items;
        }
    }
    r.description = technique->describe();
    return r;
}

Rendered render(const Scene& scene, const StyledLines& lines, const Camera& camera) {
    return render(scene, lines, std::vector<Camera>{camera});
}

// Many opaque tubes packed in a small ball: most are hidden behind the front layers.
StyledLines denseBall(std::uint32_t seed, int polylines, float alpha) {
    RandomSceneOptions o;
    o.polylines = polylines;
    o.minSegments = 3;
    o.maxSegments = 6;
    o.radiusMin = 0.04f;
    o.radiusRatio = 2.0f;
    o.stepMin = 0.1f;
    o.stepMax = 0.25f;
    o.maxBendDeg = 50.0f;
    o.extent = 0.35f;
    StyledLines lines = randomLineScene(seed, o);
    for (glm::vec4& c : lines.color) c.w = alpha;
    return lines;
}

Scene baseScene(int w, int h) {
    Scene scene;
    scene.image.width = w;
    scene.image.height = h;
    return scene;
}

// A k-buffer (k = 4) scene without AOVs: the transparent images the slicing tests compare.
Scene kbufferScene(int w, int h) {
    Scene scene = baseScene(w, h);
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
    scene.render.transparency = Transparency::KBuffer;
    scene.render.kbufferK = 4;
    return scene;
}

// CPU twin of shaders/cull_pyramid.comp: the last texel of an odd-sized row / column also takes
// the leftover source texel.
std::vector<float> reduceLevel(const std::vector<float>& src, glm::ivec2 srcSize, glm::ivec2 size, bool takeMax) {
    std::vector<float> dst(std::size_t(size.x) * size.y);
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            const int x1 = x == size.x - 1 ? srcSize.x - 1 : std::min(2 * x + 1, srcSize.x - 1);
            const int y1 = y == size.y - 1 ? srcSize.y - 1 : std::min(2 * y + 1, srcSize.y - 1);
            float v = src[std::size_t(2 * y) * srcSize.x + 2 * x];
            for (int v_ = 2 * y; v_ <= y1; ++v_)
                for (int u = 2 * x; u <= x1; ++u) {
                    const float s = src[std::size_t(v_) * srcSize.x + u];
                    v = takeMax ? std::max(v, s) : std::min(v, s);
                }
            dst[std::size_t(y) * size.x + x] = v;
        }
    return dst;
}

TEST_F(GlTest, culling_pyramid_levels_are_the_exact_max_and_min_reductions_for_odd_sizes) {
    const StyledLines lines = denseBall(9, 4, 1.0f);
    for (glm::ivec2 size : {glm::ivec2(37, 23), glm::ivec2(64, 1), glm::ivec2(5, 80)}) {
        // A source texture of random values in [0, 1): depth scaled by farDepth = 3 (max), or
        // alpha (min).
        std::mt19937 rng(size.x * 131 + size.y);
        std::vector<float> rgba(4 * std::size_t(size.x) * size.y), red(std::size_t(size.x) * size.y);
        for (std::size_t i = 0; i < red.size(); ++i) {
            red[i] = float(rng() >> 8) / 16777216.0f;
            rgba[4 * i + 0] = rgba[4 * i + 3] = red[i];
        }
        gl::Texture source = gl::makeTexture2D(GL_RGBA32F, size.x, size.y);
        glTextureSubImage2D(source.id(), 0, 0, 0, size.x, size.y, GL_RGBA, GL_FLOAT, rgba.data());
        const gl::LineGeometry geometry = gl::LineGeometry::create(lines, BillboardPath::Compute);
        for (bool takeMax : {true, false}) {
            SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y) + (takeMax ? " max" : " min"));
            gl::HierarchicalCulling culling = gl::HierarchicalCulling::create(
                takeMax ? gl::HierarchicalCulling::Target::MaxDepth : gl::HierarchicalCulling::Target::MinOpacity,
                CullingSpec{}, geometry);
            culling.build(source, size.x, size.y, 3.0f);
            std::vector<float> expected = red;
            if (takeMax)
                for (float& v : expected) v *= 3.0f;
            glm::ivec2 srcSize = size, levelSize{0};
            for (int level = 0;; ++level) {
                glm::ivec2 want = glm::max(srcSize / 2, glm::ivec2(1));
                expected = reduceLevel(expected, srcSize, want, takeMax);
                const std::vector<float> got = culling.readLevel(level, levelSize);
                ASSERT_EQ(levelSize, want) << "level " << level;
                EXPECT_TRUE(got == expected) << "level " << level;
                srcSize = want;
                if (want == glm::ivec2(1)) break;
            }
        }
    }
}

// Pixels whose colour, depth, normal or id differ in any bit.
std::size_t differingPixels(const FrameImages& a, const FrameImages& b) {
    EXPECT_EQ(a.rgba.size(), b.rgba.size());
    EXPECT_EQ(a.normal.size(), b.normal.size());
    EXPECT_EQ(a.id.size(), b.id.size());
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        bool same = a.depth[i] == b.depth[i] && a.id[i] == b.id[i];
        for (int c = 0; c < 4; ++c) same = same && a.rgba[4 * i + c] == b.rgba[4 * i + c];
        for (int c = 0; c < 3; ++c) same = same && a.normal[3 * i + c] == b.normal[3 * i + c];
        n += same ? 0 : 1;
    }
    return n;
}

std::size_t coveredPixels(const FrameImages& f) {
    return std::size_t(std::count_if(f.depth.begin(), f.depth.end(), [](float d) { return std::isfinite(d); }));
}

// Culling only removes hidden work, so every pixel is the unculled one, bit for bit. That includes
// depth ties: where consecutive segments of a polyline meet, both reach some pixels at the same
// stored depth with normals a little apart; the depth test keeps whichever was drawn first, and
// culling draws in another order (sorted slices). Both views have such pixels: had the surface
// attributes pass not settled ties by segment index (shaders/surface_attributes.frag), 64 pixels
// of the far view and 110 of the near view (the ball fills the frame, most segments are culled or
// outside it) would differ, on every billboard path.
// With the per-fragment test (what GPUs run) and without it (llvmpipe's default): both cull.
TEST_F(GlTest, opaque_culling_gives_the_unculled_image_and_culls_most_of_a_dense_scene) {
    using FragmentTest = gl::HierarchicalCulling::FragmentTest;
    struct Reset {
        ~Reset() { gl::HierarchicalCulling::setFragmentTest(FragmentTest::Auto); }
    } reset;
    const int w = 96, h = 72;
    const StyledLines lines = denseBall(5, 1000, 1.0f);
    for (const auto& [cam, label] :
         {std::pair{lookAt({0.3f, 0.4f, 2.0f}), "far view"}, std::pair{lookAt({0.1f, 0.1f, 1.2f}), "near view"}}) {
        for (BillboardPath path : {BillboardPath::Compute, BillboardPath::Vertex, BillboardPath::Geometry}) {
            Scene scene = baseScene(w, h);
            scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = true;
            scene.render.billboards = path;
            const Rendered off = render(scene, lines, cam);
            EXPECT_FALSE(off.hadCullingStage);
            const std::size_t covered = coveredPixels(off.images);
            EXPECT_GT(covered, std::size_t(w) * h / 4);
            scene.render.culling.enabled = true;
            for (FragmentTest test : {FragmentTest::On, FragmentTest::Off}) {
                SCOPED_TRACE(std::string(label) + ", billboard path " + std::to_string(int(path)) +
                             (test == FragmentTest::On ? ", fragment test" : ", no fragment test"));
                gl::HierarchicalCulling::setFragmentTest(test);
                const Rendered on = render(scene, lines, cam);
                ASSERT_TRUE(on.hadCullingStage);
                EXPECT_EQ(on.description["culling"]["fragment_test"].get<std::string>().starts_with("in the shader"),
                          test == FragmentTest::On);
                // Not vacuous: at least half of the primitives are culled or outside the view.
                EXPECT_GE(on.culled + on.outsideView, lines.segmentCount() / 2) << "of " << lines.segmentCount();
                EXPECT_GT(on.culled, lines.segmentCount() / 4) << "of " << lines.segmentCount();
                EXPECT_EQ(differingPixels(off.images, on.images), 0u) << "of " << covered << " covered pixels";
            }
        }
    }
}

TEST_F(GlTest, opaque_culling_resorts_only_after_large_camera_changes) {
    const StyledLines lines = denseBall(6, 40, 1.0f);
    Scene scene = baseScene(32, 24);
    scene.render.culling.enabled = true;
    // Orbit in 3-degree steps with only the angle rule: a re-sort when the turn since the last
    // sort exceeds 10 degrees, i.e. at 12 degrees: frames 0, 4, 8, 12.
    scene.render.culling.resortAngleDeg = 10.0f;
    scene.render.culling.resortDistance = 100.0f;
    std::vector<Camera> cams;
    for (int i = 0; i < 13; ++i) {
        const float a = glm::radians(3.0f * float(i));
        cams.push_back(lookAt({2.0f * std::sin(a), 0.3f, 2.0f * std::cos(a)}));
    }
    const Rendered orbit = render(scene, lines, cams);
    EXPECT_EQ(orbit.description["sorts_performed"].get<int>(), 4);
    // Only the distance rule: moving the eye by 5 % of its distance keeps the order, 20 % sorts.
    scene.render.culling.resortAngleDeg = 180.0f;
    scene.render.culling.resortDistance = 0.1f;
    const Rendered dolly =
        render(scene, lines, std::vector<Camera>{lookAt({0, 0, 2.0f}), lookAt({0, 0, 1.9f}), lookAt({0, 0, 1.6f})});
    EXPECT_EQ(dolly.description["sorts_performed"].get<int>(), 2);
}

void expectCulledWithinBound(const Rendered& culled, const Rendered& unculled, const FrameImages* peeled,
                             float threshold, const std::string& label) {
    const std::size_t n = culled.images.rgba.size();
    ASSERT_EQ(n, unculled.images.rgba.size());
    const double bound = 1.0 - threshold + 1e-5;  // fp32 accumulation slack
    double worst = 0, worstVsPeel = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = std::abs(double(culled.images.rgba[i]) - unculled.images.rgba[i]);
        worst = std::max(worst, d);
        EXPECT_LE(d, bound) << label << ": channel " << i;
        if (peeled) {
            const double e = std::abs(double(culled.images.rgba[i]) - peeled->rgba[i]);
            const double e0 = std::abs(double(unculled.images.rgba[i]) - peeled->rgba[i]);
            worstVsPeel = std::max(worstVsPeel, e - e0);
            EXPECT_LE(e, e0 + bound) << label << ": channel " << i << " vs depth peeling";
        }
    }
    ::testing::Test::RecordProperty(label + "_max_change", std::to_string(worst));
}

TEST_F(GlTest, transparent_culling_changes_pixels_by_at_most_one_minus_threshold) {
    const int w = 64, h = 48;
    const StyledLines lines = denseBall(7, 600, 0.6f);
    const Camera cam = lookAt({0.2f, -0.3f, 2.0f});
    Scene scene = baseScene(w, h);
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
    scene.render.transparency = Transparency::DepthPeeling;
    const Rendered peeled = render(scene, lines, cam);
    for (float threshold : {0.9f, 0.99f}) {
        for (Transparency mode : {Transparency::KBuffer, Transparency::ObjectOrder}) {
            const std::string label = std::string(mode == Transparency::KBuffer ? "kbuffer" : "object order") +
                                      ", threshold " + std::to_string(threshold);
            SCOPED_TRACE(label);
            scene.render.transparency = mode;
            scene.render.kbufferK = 8;
            scene.render.culling.enabled = false;
            const Rendered unculled = render(scene, lines, cam);
            scene.render.culling.enabled = true;
            scene.render.culling.opacityThreshold = threshold;
            const Rendered culled = render(scene, lines, cam);
            ASSERT_TRUE(culled.hadCullingStage);
            // Not vacuous: the scene is dense enough that pixels pass the threshold and whole
            // segments are culled.
            EXPECT_GT(culled.culled, lines.segmentCount() / 50) << "of " << lines.segmentCount();
            expectCulledWithinBound(culled, unculled, &peeled.images, threshold, label);
        }
    }
}

// The per-fragment test of transparent culling (the pixel's level-1 pyramid texel: the least
// opacity of its 2 x 2 pixels) skips exactly the fragments of hidden pixels: a wall of nearly
// opaque tubes in front, one tube behind it that also passes beside it, one segment per slice.
// Where the wall hides the pixel the culled image is the wall alone; everywhere else it is the
// unculled image, bit for bit.
TEST_F(GlTest, transparent_culling_skips_exactly_the_fragments_of_hidden_pixels) {
    const int w = 64, h = 48;  // even: the level-1 texels are the same 2 x 2 blocks in image rows
    const float threshold = 0.9f;
    std::vector<TestPolyline> wall;
    for (int i = 0; i < 5; ++i) {
        const float y = -0.26f + 0.13f * float(i);  // 0.01 apart: no pixel sees two of them
        wall.push_back({{{-0.3f, y, 0.3f}, 0.06f, {0.9f, 0.3f, 0.2f, 0.97f}},
                        {{0.3f, y, 0.3f}, 0.06f, {0.9f, 0.3f, 0.2f, 0.97f}}});
    }
    std::vector<TestPolyline> all = wall;
    all.push_back({{{-1.5f, 0.02f, -0.5f}, 0.05f, {0.2f, 0.4f, 0.9f, 0.6f}},
                   {{1.5f, 0.02f, -0.5f}, 0.05f, {0.2f, 0.4f, 0.9f, 0.6f}}});
    const Camera cam = lookAt({0.0f, 0.0f, 2.0f});
    Scene scene = baseScene(w, h);
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
    scene.render.transparency = Transparency::ObjectOrder;  // the target's alpha is the composite's
    const FrameImages front = render(scene, makeStyledLines(wall), cam).images;
    const FrameImages unculled = render(scene, makeStyledLines(all), cam).images;
    scene.render.culling.enabled = true;
    scene.render.culling.opacityThreshold = threshold;
    scene.render.culling.slices = int(all.size());
    const Rendered culled = render(scene, makeStyledLines(all), cam);
    ASSERT_TRUE(culled.hadCullingStage);
    EXPECT_EQ(culled.culled, 0u);  // the back tube reaches past the wall: no whole segment hidden

    auto pixel = [](const FrameImages& im, int x, int y) {
        const std::size_t i = 4 * (std::size_t(y) * std::size_t(im.width) + std::size_t(x));
        return glm::vec4(im.rgba[i], im.rgba[i + 1], im.rgba[i + 2], im.rgba[i + 3]);
    };
    int hidden = 0, hiddenBehind = 0, shown = 0, shownBehind = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float least = 1.0f;  // the texel's least opacity after the wall's slices
            for (int v = y & ~1; v <= (y | 1); ++v)
                for (int u = x & ~1; u <= (x | 1); ++u) least = std::min(least, pixel(front, u, v).w);
            const glm::vec4 c = pixel(culled.images, x, y);
            const bool behind = pixel(unculled, x, y) != pixel(front, x, y);  // the back tube adds here
            if (least > threshold) {
                ++hidden;
                hiddenBehind += behind ? 1 : 0;
                EXPECT_EQ(c, pixel(front, x, y)) << "hidden pixel " << x << ", " << y;
            } else {
                ++shown;
                shownBehind += behind ? 1 : 0;
                EXPECT_EQ(c, pixel(unculled, x, y)) << "pixel " << x << ", " << y;
            }
        }
    // Not vacuous: the back tube lies behind hidden pixels and beside the wall.
    EXPECT_GT(hiddenBehind, 20) << "of " << hidden << " hidden pixels";
    EXPECT_GT(shownBehind, 20) << "of " << shown << " other pixels";
}

TEST_F(GlTest, slicing_without_culling_leaves_the_kbuffer_bit_identical) {
    const int w = 80, h = 60;
    const StyledLines lines = denseBall(8, 200, 0.4f);
    const Camera cam = lookAt({-0.4f, 0.2f, 2.1f});
    Scene scene = kbufferScene(w, h);
    const Rendered single = render(scene, lines, cam);
    // Opacity never exceeds 1, so with threshold 1 nothing is culled: only the slicing remains.
    scene.render.culling.enabled = true;
    scene.render.culling.opacityThreshold = 1.0f;
    for (BillboardPath path : {BillboardPath::Compute, BillboardPath::Geometry}) {
        scene.render.billboards = path;
        for (int slices : {1, 7, 64}) {
            scene.render.culling.slices = slices;
            const Rendered sliced = render(scene, lines, cam);
            EXPECT_EQ(sliced.culled, 0u);
            EXPECT_TRUE(sliced.images.rgba == single.images.rgba) << slices << " slices, path " << int(path);
        }
    }
}

// Segments of `lines` whose bounding sphere lies outside the frustum by more than a rounding margin:
// the frustum pass must find at least these.
std::size_t clearlyOutside(const StyledLines& lines, const Camera& cam, int w, int h) {
    const ViewFrustum frustum = viewFrustum(cam, w, h, 2.0f);
    std::size_t n = 0;
    for (std::size_t s = 0; s < lines.segmentCount(); ++s) {
        const glm::vec4 a = lines.positionRadius[lines.segmentVertices[2 * s]];
        const glm::vec4 b = lines.positionRadius[lines.segmentVertices[2 * s + 1]];
        const glm::vec3 c = 0.5f * (glm::vec3(a) + glm::vec3(b));
        const float r = 0.5f * glm::distance(glm::vec3(a), glm::vec3(b)) + std::max(a.w, b.w);
        n += frustum.excludesSphere(c, r * 1.01f + 1e-4f) ? 1 : 0;
    }
    return n;
}

// A near view into the dense ball: many segments lie outside the view. The depth slices are cut
// from the segments in view and the rest is not drawn; the opaque image is still the unculled one,
// also when the order is reused for a turned camera (the rest is then drawn as one more slice),
// and the k-buffer with nothing to cull (threshold 1) stays bit-identical.
TEST_F(GlTest, culling_slices_what_is_in_view_and_skips_the_rest_without_changing_the_image) {
    const int w = 80, h = 60;
    const StyledLines lines = denseBall(9, 1000, 1.0f);
    // Looking at the left part of the ball, then (same eye: opaque culling re-sorts on eye moves
    // only) at its right part, which was mostly outside the first view.
    const Camera cam = lookAt({0.0f, 0.1f, 0.8f}, {-0.35f, 0.0f, 0.0f});
    const Camera turned = lookAt({0.0f, 0.1f, 0.8f}, {0.35f, 0.0f, 0.0f});
    const std::size_t outside = clearlyOutside(lines, cam, w, h);
    ASSERT_GT(outside, lines.segmentCount() / 4) << "the test view must leave many segments outside";

    Scene scene = baseScene(w, h);
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = true;
    const Rendered off = render(scene, lines, cam);
    const Rendered offTurned = render(scene, lines, turned);
    scene.render.culling.enabled = true;
    scene.render.culling.resortAngleDeg = 10.0f;
    const Rendered on = render(scene, lines, cam);
    const Rendered onTurned = render(scene, lines, std::vector<Camera>{cam, turned});
    EXPECT_GE(on.outsideView, outside);
    EXPECT_LT(on.outsideView, lines.segmentCount());
    EXPECT_EQ(onTurned.description["sorts_performed"].get<int>(), 1);
    for (const auto& [culled, unculled, label] :
         {std::tuple{&on, &off, "sorted for this view"}, std::tuple{&onTurned, &offTurned, "order reused"}}) {
        SCOPED_TRACE(label);
        const std::size_t covered = coveredPixels(unculled->images);
        EXPECT_GT(covered, std::size_t(w) * h / 2);
        EXPECT_EQ(differingPixels(unculled->images, culled->images), 0u) << "of " << covered << " covered pixels";
    }

    // Transparent: threshold 1 culls nothing, so only the slicing of what is in view remains.
    StyledLines glassy = lines;
    for (glm::vec4& c : glassy.color) c.w = 0.4f;
    Scene t = kbufferScene(w, h);
    const Rendered all = render(t, glassy, cam);
    t.render.culling.enabled = true;
    t.render.culling.opacityThreshold = 1.0f;
    const Rendered sliced = render(t, glassy, cam);
    EXPECT_GE(sliced.outsideView, outside);
    EXPECT_EQ(sliced.culled, 0u);
    EXPECT_TRUE(sliced.images.rgba == all.images.rgba);
}

}  // namespace
}  // namespace tc::test
