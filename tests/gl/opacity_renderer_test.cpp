// Opacity optimization on the GPU (gl/opacity_renderer.cpp): two crossing lines, a short
// unimportant one in front of a long important one (importance "length"), seen orthographically
// from +z so the crossing is known in pixels.
#include "gl/opacity_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "core/scene.h"
#include "core/technique.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

constexpr int kSize = 64;
const glm::vec4 kFrontColor{1.0f, 0.0f, 0.0f, 1.0f};  // the short, unimportant line: red
const glm::vec4 kBackColor{0.0f, 0.0f, 1.0f, 1.0f};   // the long, important line: blue

StyledLines crossingLines() {
    TestPolyline front, back;
    for (int k = 0; k <= 8; ++k) {
        const float t = float(k) / 8.0f;
        front.push_back({{-0.5f + t, 0.0f, 0.5f}, 0.08f, kFrontColor});  // along x, nearer the eye
        back.push_back({{0.0f, -0.9f + 1.8f * t, 0.0f}, 0.08f, kBackColor});
    }
    return makeStyledLines({front, back});
}

Scene opacityScene(float q) {
    Scene scene;
    scene.image.width = scene.image.height = kSize;
    scene.render.technique = RenderTechnique::Rasterized;
    scene.render.transparency = Transparency::OpacityOptimization;
    scene.render.opacity.q = q;
    scene.render.opacity.r = q / 10;
    scene.render.opacity.segmentsPerLine = 4;
    scene.render.opacity.importance = OpacityOptimizationSpec::Importance::Length;
    scene.render.opacity.tolerance = 1e-8f;
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
    return scene;
}

Camera topCamera() {
    Camera cam;
    cam.eye = {0, 0, 3};
    cam.target = {0, 0, 0};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 2.0f;
    return cam;
}

struct Frame {
    FrameImages images;
    gl::OpacityRenderer::FrameStats stats;
    Eigen::VectorXd opacity;
};

Frame renderOnce(gl::OpacityRenderer& r, int frame = 0, const Camera& cam = topCamera(), int size = kSize) {
    Frame f;
    gl::StageTimer timer;
    r.render(tc::FrameSetup{frame, cam, size, size}, f.images, timer);
    timer.collect();
    f.stats = r.lastStats();
    f.opacity = r.displayedOpacities();
    return f;
}

glm::vec4 pixel(const FrameImages& im, int x, int y) {
    const float* p = &im.rgba[4 * (std::size_t(y) * im.width + x)];
    return {p[0], p[1], p[2], p[3]};
}

TEST_F(GlTest, opacity_optimization_keeps_the_important_line_and_fades_its_occluder) {
    const StyledLines lines = crossingLines();
    // createTechnique dispatches render.transparency "opacity_optimization" here.
    std::unique_ptr<tc::Technique> t = gl::createTechnique(opacityScene(0.0f), lines);
    auto* plain = dynamic_cast<gl::OpacityRenderer*>(t.get());
    ASSERT_NE(plain, nullptr);
    Frame off = renderOnce(*plain);
    EXPECT_EQ(off.stats.overflow, 0u);
    EXPECT_GT(off.stats.fragments, 200u);
    EXPECT_GT(off.stats.hNonZeros, 0u);  // the crossing is seen in the lists...
    ASSERT_TRUE(off.stats.solve.converged);
    for (Eigen::Index i = 0; i < off.opacity.size(); ++i) EXPECT_NEAR(off.opacity[i], 1.0, 1e-9);  // ...but q = 0
    // The crossing pixel (image centre) shows the opaque front line.
    const glm::vec4 c0 = pixel(off.images, kSize / 2, kSize / 2);
    EXPECT_NEAR(c0.w, 1.0f, 1e-4f);
    EXPECT_GT(c0.x, 0.2f);
    EXPECT_GT(c0.x, 10 * c0.z);  // red (blue only from the white specular term)

    auto strong = gl::OpacityRenderer::create(opacityScene(400.0f), lines);
    Frame on = renderOnce(*strong);
    ASSERT_TRUE(on.stats.solve.converged);
    EXPECT_LE(on.stats.solve.residual, 1e-8);
    ASSERT_EQ(on.opacity.size(), 8);
    // Importance by length: the back line (1.8 long) has g = 1, the front one (1.0) g = 1 / 1.8.
    EXPECT_NEAR(strong->importance()[0], 1 / 1.8, 1e-5);
    EXPECT_NEAR(strong->importance()[4], 1.0, 1e-6);
    // Parts 1, 2 of the front line (the middle, w in [0.5, 2.5]) cover the back line: faded.
    // The back line stays opaque.
    EXPECT_LT(std::min(on.opacity[1], on.opacity[2]), 0.5);
    for (int k = 4; k < 8; ++k) EXPECT_GT(on.opacity[k], 0.99) << k;
    // The crossing now shows mostly the back line through the faded front line.
    const glm::vec4 c1 = pixel(on.images, kSize / 2, kSize / 2);
    EXPECT_NEAR(c1.w, 1.0f, 1e-3f);
    EXPECT_GT(c1.z, 0.1f);
    EXPECT_LT(c1.x, c0.x * 0.6f);
    // Away from the crossing the back line is drawn as before (fully opaque, blue).
    const glm::vec4 far = pixel(on.images, kSize / 2, 4);
    EXPECT_NEAR(far.w, 1.0f, 1e-4f);
    EXPECT_GT(far.z, 0.2f);
}

TEST_F(GlTest, opacity_optimization_blends_toward_the_new_solution_across_frames) {
    const StyledLines lines = crossingLines();
    Scene scene = opacityScene(400.0f);
    scene.render.opacity.blend = 0.5f;
    auto r = gl::OpacityRenderer::create(scene, lines);
    Frame f0 = renderOnce(*r, 0);  // the first frame shows its solution
    Frame f1 = renderOnce(*r, 1);
    // Same view: warm started at the solution, nothing left to do.
    EXPECT_LE(f1.stats.solve.iterations, 1);
    EXPECT_LE((f0.opacity - f1.opacity).lpNorm<Eigen::Infinity>(), 1e-6);

    // Seen from +x the lines do not overlap (all opacities 1); then from +z the front line's
    // middle fades, but the displayed opacities only move half-way per frame.
    Camera side = topCamera();
    side.eye = {3, 0, 0};
    auto moving = gl::OpacityRenderer::create(scene, lines);
    Frame s0 = renderOnce(*moving, 0, side);
    EXPECT_EQ(s0.stats.hNonZeros, 0u);
    for (Eigen::Index i = 0; i < s0.opacity.size(); ++i) EXPECT_NEAR(s0.opacity[i], 1.0, 1e-9);
    Frame s1 = renderOnce(*moving, 1);
    const Eigen::VectorXd& solution = s1.stats.solve.x;
    EXPECT_LT(solution[1], 0.5);
    EXPECT_LE((s1.opacity - 0.5 * (Eigen::VectorXd::Ones(8) + solution)).lpNorm<Eigen::Infinity>(), 1e-12);
    Frame s2 = renderOnce(*moving, 2);
    EXPECT_LE((s2.opacity - 0.5 * (s1.opacity + s2.stats.solve.x)).lpNorm<Eigen::Infinity>(), 1e-12);
    EXPECT_LT(s2.opacity[1], s1.opacity[1]);
}

TEST_F(GlTest, opacity_optimization_from_the_fragment_lists_matches_the_assembled_occlusion_matrix) {
    // render.opacity.occlusion "fragments" forms the products with H from the lists by prefix
    // sums (core/fragment_occlusion.h); no h_ij reaches 1 here, so the clamp of the assembled
    // path changes nothing and the opacities and images agree.
    const StyledLines lines = crossingLines();
    Scene scene = opacityScene(400.0f);
    scene.render.opacity.occlusion = OpacityOptimizationSpec::Occlusion::Assembled;
    auto assembled = gl::OpacityRenderer::create(scene, lines);
    Frame a = renderOnce(*assembled);
    scene.render.opacity.occlusion = OpacityOptimizationSpec::Occlusion::Fragments;
    auto fromLists = gl::OpacityRenderer::create(scene, lines);
    Frame b = renderOnce(*fromLists);
    EXPECT_FALSE(a.stats.fromFragments);
    EXPECT_TRUE(b.stats.fromFragments);
    EXPECT_EQ(b.stats.hNonZeros, 0u);
    EXPECT_EQ(a.stats.pairs, b.stats.pairs);
    EXPECT_GT(b.stats.pairs, 0u);
    ASSERT_TRUE(b.stats.solve.converged);
    EXPECT_LT(a.opacity.minCoeff(), 0.5);
    EXPECT_LE((a.opacity - b.opacity).lpNorm<Eigen::Infinity>(), 1e-5);
    float diff = 0;
    for (std::size_t k = 0; k < a.images.rgba.size(); ++k)
        diff = std::max(diff, std::abs(a.images.rgba[k] - b.images.rgba[k]));
    EXPECT_LE(diff, 1e-4f);
}

TEST_F(GlTest, opacity_optimization_at_half_occlusion_resolution_stays_near_the_full_resolution_opacities) {
    // render.opacity.occlusion_scale 0.5: h_ij from every second pixel's list in x and y
    // (normalised by the part fragment counts of the same pixels, so resolution-independent up to
    // sampling); the image is still resolved at full size from all lists. At 256 x 256 px the
    // tubes are ~20 px wide and the two agree to 4e-5 (0.08 at 128 px and 0.16 at 64 px, where a
    // crossing is only a few pixels of the half-size sampling).
    const int size = 256;
    const StyledLines lines = crossingLines();
    Scene scene = opacityScene(400.0f);
    scene.image.width = scene.image.height = size;
    auto fullRenderer = gl::OpacityRenderer::create(scene, lines);
    Frame full = renderOnce(*fullRenderer, 0, topCamera(), size);
    scene.render.opacity.occlusionScale = 0.5f;
    auto halfRenderer = gl::OpacityRenderer::create(scene, lines);
    Frame half = renderOnce(*halfRenderer, 0, topCamera(), size);
    EXPECT_EQ(full.stats.occlusionWidth, size);
    EXPECT_EQ(full.stats.occlusionHeight, size);
    EXPECT_EQ(half.stats.occlusionWidth, size / 2);
    EXPECT_EQ(half.stats.occlusionHeight, size / 2);
    // A quarter of the pixels, so about a quarter of the fragments.
    EXPECT_NEAR(double(half.stats.occlusionFragments), double(full.stats.occlusionFragments) / 4,
                0.1 * double(full.stats.occlusionFragments) / 4);
    EXPECT_EQ(half.stats.fragments, full.stats.fragments);  // the lists themselves are full size
    ASSERT_TRUE(half.stats.solve.converged);
    EXPECT_LT(full.opacity.minCoeff(), 0.5);  // the occluder really is faded
    EXPECT_LE((full.opacity - half.opacity).lpNorm<Eigen::Infinity>(), 0.01);
    EXPECT_EQ(half.images.width, size);
    float diff = 0;
    for (std::size_t k = 0; k < full.images.rgba.size(); ++k)
        diff = std::max(diff, std::abs(full.images.rgba[k] - half.images.rgba[k]));
    EXPECT_LE(diff, 0.01f);
}

TEST_F(GlTest, opacity_optimization_with_a_coarse_start_reaches_the_same_minimiser) {
    // render.opacity.coarse_scale only changes where the solve starts (the minimiser of the
    // system of the lists subsampled at 0.25); the solve of the full system then stops at the same
    // tolerance (1e-8 here), so the opacities agree to about that, in both frames.
    const StyledLines lines = crossingLines();
    Scene scene = opacityScene(400.0f);
    const int size = 256;
    scene.image.width = scene.image.height = size;
    auto plain = gl::OpacityRenderer::create(scene, lines);
    scene.render.opacity.coarseScale = 0.25f;
    auto twoLevel = gl::OpacityRenderer::create(scene, lines);
    Camera turned = topCamera();
    turned.eye = {0.3f, 0.0f, 3.0f};
    for (const Camera& cam : {topCamera(), turned}) {
        Frame a = renderOnce(*plain, 0, cam, size);
        Frame b = renderOnce(*twoLevel, 0, cam, size);
        EXPECT_EQ(a.stats.coarse.products, 0);
        EXPECT_GT(b.stats.coarse.products, 0);
        ASSERT_TRUE(b.stats.coarse.converged);
        ASSERT_TRUE(b.stats.solve.converged);
        EXPECT_LT(a.opacity.minCoeff(), 0.5);
        EXPECT_LE((a.opacity - b.opacity).lpNorm<Eigen::Infinity>(), 1e-6);
    }
}

TEST_F(GlTest, opacity_optimization_counts_fragment_pool_overflow_instead_of_failing) {
    // 220 x 220 px: target + heads take 968,000 of the 1 MB budget, leaving 4,028 nodes.
    std::vector<TestPolyline> many;
    for (int l = 0; l < 12; ++l) {
        TestPolyline p;
        for (int k = 0; k <= 4; ++k)
            p.push_back({{-0.9f + 0.45f * float(k), -0.8f + 0.14f * float(l), 0.1f * float(l)}, 0.12f, kFrontColor});
        many.push_back(p);
    }
    const StyledLines lines = makeStyledLines(many);
    Scene scene = opacityScene(1.0f);
    scene.image.width = scene.image.height = 220;
    scene.render.memoryBudgetMb = 1;
    auto r = gl::OpacityRenderer::create(scene, lines);
    FrameImages im;
    gl::StageTimer timer;
    r->render(tc::FrameSetup{0, topCamera(), 220, 220}, im, timer);
    timer.collect();
    const auto& s = r->lastStats();
    EXPECT_EQ(s.capacity, 4028u);
    EXPECT_GT(s.overflow, 0u);
    EXPECT_EQ(s.fragments, s.capacity + s.overflow);
    EXPECT_EQ(im.rgba.size(), 4u * 220 * 220);
}

// style.halo (Everts et al. 2009, as Günther et al. 2013, Sect. 4.2 draw their lines): 1 px =
// 2/64 world units, radius 0.08 = 2.56 px, a ring of one radius. Rows 27 and 28 (pixel centres at
// y = 0.141 and 0.109) lie outside the front line's silhouette (|y| < 0.08) and inside its ring
// (|y| < 0.16), as rows 35 and 36 below it; row 25 (y = 0.203) lies outside both. Column 44
// (x = 0.39) is far from the back line, columns 31, 32 (x = -+0.016) lie on it. q = 0: every
// opacity is 1, so the lines are opaque. The ring's depth reaches 4 radii (0.32) behind the front
// line's axis; the back line lies 0.5 behind it, or at the same depth.
// The same for the GL techniques that draw halos: rasterized (opacity optimization, depth peeling)
// and voxel_raycast (front-to-back compositing). raytraced equals the CPU reference with halos
// (tests/unit/raytraced_test.cpp), which depth peeling is tested against.
TEST_F(GlTest, halo_rings_a_tube_and_hides_a_line_behind_it_but_not_one_at_the_same_depth) {
    const glm::vec3 green{0.0f, 1.0f, 0.0f};
    struct Case {
        RenderTechnique technique;
        Transparency mode;
    };
    for (const Case& c : {Case{RenderTechnique::Rasterized, Transparency::OpacityOptimization},
                          Case{RenderTechnique::Rasterized, Transparency::DepthPeeling},
                          Case{RenderTechnique::VoxelRaycast, Transparency::DepthPeeling}}) {
        const Transparency mode = c.mode;
        SCOPED_TRACE(c.technique.name() + ", " + transparencyName(mode));
        for (bool equalDepth : {false, true}) {
            SCOPED_TRACE(equalDepth ? "both lines at z = 0" : "front line 0.5 in front of the back line");
            TestPolyline front, back;
            for (int k = 0; k <= 8; ++k) {
                const float t = float(k) / 8.0f;
                front.push_back({{-0.5f + t, 0.0f, equalDepth ? 0.0f : 0.5f}, 0.08f, kFrontColor});
                back.push_back({{0.0f, -0.9f + 1.8f * t, 0.0f}, 0.08f, kBackColor});
            }
            const StyledLines lines = makeStyledLines({front, back});
            Scene scene = opacityScene(0.0f);
            scene.render.technique = c.technique;
            scene.render.transparency = mode;
            // Voxels of 0.25 (the data is 1.8 long): the ring (0.16 from the axis) within one voxel.
            scene.render.vrc.resolution = 8;
            auto plainTechnique = gl::createTechnique(scene, lines);
            scene.style.halo.enabled = true;
            scene.style.halo.width = 1.0f;
            scene.style.halo.depth = 4.0f;
            scene.style.halo.color = green;
            auto haloTechnique = gl::createTechnique(scene, lines);
            FrameImages plain, haloed;
            gl::StageTimer timer;
            plainTechnique->render(tc::FrameSetup{0, topCamera(), kSize, kSize}, plain, timer);
            haloTechnique->render(tc::FrameSetup{0, topCamera(), kSize, kSize}, haloed, timer);
            timer.collect();
            // Just outside the silhouette, over the background: the halo's colour, opaque; before
            // (no halo) the background.
            for (int row : {27, 28, 35, 36}) {
                SCOPED_TRACE(row);
                EXPECT_EQ(pixel(plain, 44, row), glm::vec4(0.0f));
                const glm::vec4 h = pixel(haloed, 44, row);
                EXPECT_NEAR(h.x, 0.0f, 1e-3f);
                EXPECT_NEAR(h.y, 1.0f, 1e-3f);
                EXPECT_NEAR(h.z, 0.0f, 1e-3f);
                EXPECT_NEAR(h.w, 1.0f, 1e-3f);
            }
            EXPECT_EQ(pixel(haloed, 44, 25), glm::vec4(0.0f));  // beyond the ring
            // The tube itself is unchanged.
            EXPECT_EQ(pixel(haloed, 44, 31), pixel(plain, 44, 31));
            // Where the back line passes the front line's ring: hidden by the ring when it lies
            // 0.5 behind, seen through it at the same depth.
            for (int column : {31, 32})
                for (int row : {27, 28}) {
                    SCOPED_TRACE(testing::Message() << column << ", " << row);
                    const glm::vec4 before = pixel(plain, column, row), after = pixel(haloed, column, row);
                    EXPECT_GT(before.z, 0.2f);  // the blue back line
                    if (equalDepth) {
                        EXPECT_EQ(after, before);
                    } else {
                        EXPECT_NEAR(after.y, 1.0f, 1e-3f);
                        EXPECT_NEAR(after.z, 0.0f, 1e-3f);
                    }
                }
        }
    }
}

// image.samples = 4 (offsets -+0.375, -+0.125 px): the front line's silhouette y = 0.08 crosses
// row 29 (centre y = 0.078, samples at y = 0.090, 0.082 outside and 0.074, 0.066 inside), so that
// pixel is half covered; with ambient light only the tube is flat-coloured, and its interior and
// the background are the same as with one sample. q = 0 keeps every opacity at 1, whichever
// sample's lists the system comes from, so only coverage can change a pixel.
TEST_F(GlTest, opacity_optimization_with_samples_antialiases_silhouettes_and_keeps_flat_interiors) {
    const StyledLines lines = crossingLines();
    Scene scene = opacityScene(0.0f);
    scene.lighting.ambient = 1.0f;
    scene.lighting.diffuse = scene.lighting.specular = 0.0f;
    auto single = gl::OpacityRenderer::create(scene, lines);
    scene.image.samples = 4;
    auto multi = gl::OpacityRenderer::create(scene, lines);
    const Frame one = renderOnce(*single), four = renderOnce(*multi);
    EXPECT_EQ(four.opacity, one.opacity);
    // The silhouette: covered at the centre sample, half covered by the four.
    EXPECT_NEAR(pixel(one.images, 44, 29).w, 1.0f, 1e-6f);
    const glm::vec4 edge = pixel(four.images, 44, 29);
    EXPECT_NEAR(edge.w, 0.5f, 1e-3f);
    EXPECT_NEAR(edge.x, 0.5f * pixel(one.images, 44, 29).x, 1e-3f);
    // Flat interior and background: unchanged.
    for (int row : {30, 31, 32, 33}) {
        const glm::vec4 a = pixel(one.images, 44, row), b = pixel(four.images, 44, row);
        EXPECT_NEAR(a.w, 1.0f, 1e-6f) << row;
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(b[c], a[c], 1e-6f) << row << " " << c;
    }
    EXPECT_EQ(pixel(four.images, 44, 20), glm::vec4(0.0f));
}

// render.opacity.pipeline: the first frame solves its own system (the same image as without),
// then the camera moves from +x (no overlap, all opacities 1) to +z: the worker solves the +z
// system while frames keep coming, and the displayed opacities fade toward its solution.
TEST_F(GlTest, opacity_optimization_pipeline_converges_to_the_solution_and_keeps_a_single_frame) {
    const StyledLines lines = crossingLines();
    Scene scene = opacityScene(400.0f);
    scene.render.opacity.blend = 0.5f;
    auto direct = gl::OpacityRenderer::create(scene, lines);
    scene.render.opacity.pipeline = true;
    auto pipelined = gl::OpacityRenderer::create(scene, lines);
    const Frame a = renderOnce(*direct), b = renderOnce(*pipelined);
    EXPECT_EQ(a.images.rgba, b.images.rgba);
    EXPECT_EQ(a.opacity, b.opacity);
    EXPECT_EQ(b.stats.solvedFrame, 0);

    Camera side = topCamera();
    side.eye = {3, 0, 0};
    auto moving = gl::OpacityRenderer::create(scene, lines);
    Frame f = renderOnce(*moving, 0, side);
    for (Eigen::Index i = 0; i < f.opacity.size(); ++i) EXPECT_NEAR(f.opacity[i], 1.0, 1e-9);
    // The +z solution, solved directly (the energy is strictly convex: one minimiser).
    const Eigen::VectorXd solution = renderOnce(*direct, 1).stats.solve.x;
    ASSERT_LT(solution[1], 0.5);
    int frame = 1;
    bool sawFade = false;
    for (; frame < 2000; ++frame) {
        f = renderOnce(*moving, frame);
        if (f.stats.solvedFrame >= 1 && f.opacity[1] > solution[1] + 1e-3) sawFade = true;
        if ((f.opacity - solution).lpNorm<Eigen::Infinity>() < 1e-6) break;
        if (f.stats.solvedFrame < 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_LT((f.opacity - solution).lpNorm<Eigen::Infinity>(), 1e-6) << "after " << frame << " frames";
    EXPECT_GE(f.stats.solvedFrame, 1);
    EXPECT_TRUE(sawFade);  // faded in over frames, not jumped (blend 0.5)
}

}  // namespace
}  // namespace tc::test
