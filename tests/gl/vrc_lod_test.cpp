// Level of detail in voxel ray casting (render.vrc.lod; gl/vrc_renderer.h, shaders/vrc_lod.glsl):
//   - the levels a ray samples follow its pixel footprint (a CPU expectation from the camera and
//     the grid's distance), and a view whose voxels all cover more pixels than the footprint
//     renders exactly the image without LoD;
//   - the LoD volume integrates to Eq. 1's total (one thin tube, orthographic, pure volume);
//   - opacity acceleration climbs the levels as the opacity grows;
//   - the LoD images stay within a stated PSNR of the images without LoD and of depth peeling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <vector>

#include "core/camera.h"
#include "core/image_metrics.h"
#include "core/scene.h"
#include "core/technique.h"
#include "core/vrc_model.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl/vrc_renderer.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

// 600 random bent polylines in [-0.8, 0.8]^3 (about 4000 segments), radii 0.006..0.012.
StyledLines denseLines(float alpha) {
    RandomSceneOptions o;
    o.polylines = 600;
    o.minSegments = 4;
    o.maxSegments = 10;
    o.radiusMin = 0.006f;
    o.radiusRatio = 2.0f;
    o.stepMin = 0.05f;
    o.stepMax = 0.12f;
    o.maxBendDeg = 40.0f;
    StyledLines lines = randomLineScene(11, o);
    for (glm::vec4& c : lines.color) c.w = alpha;
    return lines;
}

Scene lodScene(int w, int h, bool transparent, bool lod, float footprint, float opacityStart) {
    Scene scene;
    scene.image.width = w;
    scene.image.height = h;
    scene.render.technique = RenderTechnique::VoxelRaycast;
    scene.render.transparency = transparent ? Transparency::KBuffer : Transparency::Opaque;
    scene.render.vrc.resolution = 32;
    scene.render.vrc.lod.enabled = lod;
    scene.render.vrc.lod.pixelFootprint = footprint;
    scene.render.vrc.lod.opacityStart = opacityStart;
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
    return scene;
}

Camera cameraAt(float distance) {
    Camera cam;
    cam.eye = glm::normalize(glm::vec3(0.7f, 0.5f, 2.3f)) * distance;
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 30.0f;
    return cam;
}

FrameImages render(Technique& t, const Scene& scene, const Camera& cam) {
    gl::StageTimer timer;
    FrameImages out;
    t.render(FrameSetup{0, cam, scene.image.width, scene.image.height}, out, timer);
    timer.collect();
    return out;
}

FrameImages render(const Scene& scene, const StyledLines& lines, const Camera& cam) {
    std::unique_ptr<Technique> t = gl::createTechnique(scene, lines);
    return render(*t, scene, cam);
}

// The LoD sample counts per level (and, last, the rays that entered the volume) of one frame.
std::vector<std::uint32_t> lodSamples(const Scene& scene, const StyledLines& lines, const Camera& cam,
                                      FrameImages* image = nullptr) {
    std::unique_ptr<gl::VrcRenderer> r = gl::VrcRenderer::create(scene, lines);
    r->enableLodStats();
    FrameImages out = render(*r, scene, cam);
    if (image) *image = std::move(out);
    return r->lodSamples();
}

TEST_F(GlTest, vrc_lod_far_view_samples_the_levels_its_pixel_footprint_predicts) {
    const StyledLines lines = denseLines(1.0f);
    const int w = 64, h = 48;
    const Scene scene = lodScene(w, h, false, true, 1.0f, 0.5f);
    VrcBuildOptions o;
    o.resolution = 32;
    const VrcModel model = buildVrcModel(lines, o);
    const int levels = int(buildVrcLodVolume(model, true).size());
    const glm::vec3 lo = model.origin, hi = model.origin + glm::vec3(model.size) * model.voxelSize;
    const glm::vec3 centre = 0.5f * (lo + hi);
    const float halfDiagonal = 0.5f * glm::length(hi - lo);
    for (float distance : {30.0f, 80.0f}) {
        SCOPED_TRACE("distance " + std::to_string(distance));
        const Camera cam = cameraAt(distance);
        // A ray meets the grid between these distances from the eye; the level at t is
        // floor(log2(footprint x pixel(t) / voxel)), pixel(t) = 2 tan(fov / 2) t / height.
        const float d = glm::length(cam.eye - centre);
        auto level = [&](float t) {
            const float pixel = 2.0f * std::tan(glm::radians(cam.fovYDeg) * 0.5f) * t / float(h);
            return std::min(int(std::floor(std::log2(pixel / model.voxelSize))), levels - 1);
        };
        const int lowest = level(d - halfDiagonal), highest = level(d + halfDiagonal);
        ASSERT_GE(lowest, 1);
        const std::vector<std::uint32_t> samples = lodSamples(scene, lines, cam);
        ASSERT_EQ(samples.size(), std::size_t(gl::VrcRenderer::kMaxLodLevels + 1));
        std::uint32_t inRange = 0;
        for (int l = 0; l < gl::VrcRenderer::kMaxLodLevels; ++l) {
            std::printf("distance %.0f level %d: %u samples (expected levels %d..%d)\n", distance, l, samples[l],
                        lowest, highest);
            if (l < lowest || l > highest) {
                EXPECT_EQ(samples[l], 0u) << "level " << l;
            } else {
                inRange += samples[l];
            }
        }
        EXPECT_GT(inRange, 0u);
        EXPECT_GT(samples.back(), 0u);  // rays that entered the volume
    }
}

TEST_F(GlTest, vrc_lod_near_view_whose_voxels_cover_several_pixels_renders_the_image_without_lod) {
    // At distance 2.5 a voxel (~0.055) covers at least 1.3 pixels of 64 x 48 at 30 degrees (at
    // the far corner of the grid): footprint 1 never switches, and nothing in the image may change.
    const StyledLines lines = denseLines(0.3f);
    const Camera cam = cameraAt(2.5f);
    for (bool transparent : {false, true}) {
        SCOPED_TRACE(transparent ? "transparent" : "opaque");
        // opacity_start 1: no opacity acceleration, the footprint alone.
        FrameImages withLod;
        const std::vector<std::uint32_t> samples =
            lodSamples(lodScene(64, 48, transparent, true, 1.0f, 1.0f), lines, cam, &withLod);
        const FrameImages without = render(lodScene(64, 48, transparent, false, 1.0f, 1.0f), lines, cam);
        EXPECT_EQ(samples.back(), 0u);
        EXPECT_EQ(withLod.rgba, without.rgba);
    }
}

TEST_F(GlTest, vrc_lod_volume_of_one_thin_tube_integrates_to_eq1_total) {
    // One straight tube across an orthographic view, the whole ray in the LoD volume
    // (opacity_start 0, alpha small enough to stay at level 0): sum over pixels of the optical
    // depth -ln(1 - alpha_pixel) x pixel area = the integral of sigma = (pi / 2) r l alpha.
    const float r = 0.01f, alpha = 0.05f, length = 1.2f;
    // A second tube of alpha 0 (no extinction) along the diagonal widens the grid: rays march the
    // volume inside the grid box only, and a sample's trilinear reach half a voxel past the box's
    // faces would be lost for a tube one voxel from them.
    const StyledLines lines = makeStyledLines(
        {{{{-0.6f, 0.0f, 0.0f}, r, {0.5f, 0.5f, 0.5f, alpha}}, {{0.6f, 0.0f, 0.0f}, r, {0.5f, 0.5f, 0.5f, alpha}}},
         {{{-0.6f, -0.5f, -0.5f}, r, {0.5f, 0.5f, 0.5f, 0.0f}}, {{0.6f, 0.5f, 0.5f}, r, {0.5f, 0.5f, 0.5f, 0.0f}}}});
    const int w = 128, h = 96;
    Scene scene = lodScene(w, h, true, true, 0.0f, 0.0f);
    scene.render.vrc.resolution = 24;
    scene.render.vrc.opacityThreshold = 1.0f;
    Camera cam;
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 1.2f;
    cam.eye = {0.0f, 0.0f, 3.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    FrameImages img;
    const std::vector<std::uint32_t> samples = lodSamples(scene, lines, cam, &img);
    EXPECT_EQ(std::accumulate(samples.begin() + 1, samples.end() - 1, 0u), 0u);  // level 0 only
    EXPECT_GT(samples[0], 0u);
    const double pixel = double(cam.orthoHeight) / h;
    double integral = 0;
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i) integral -= std::log(1.0 - double(img.rgba[4 * i + 3]));
    integral *= pixel * pixel;
    const double expected = 0.5 * 3.14159265358979323846 * r * length * alpha;
    std::printf("LoD volume integral %.6g, expected %.6g\n", integral, expected);
    EXPECT_NEAR(integral, expected, 0.03 * expected);
}

TEST_F(GlTest, vrc_lod_opacity_acceleration_climbs_levels_as_the_opacity_grows) {
    const StyledLines lines = denseLines(0.5f);
    const Camera cam = cameraAt(3.0f);
    const std::vector<std::uint32_t> samples = lodSamples(lodScene(64, 48, true, true, 0.0f, 0.5f), lines, cam);
    EXPECT_GT(samples.back(), 0u);
    // Level 0 from opacity 0.5, level 1 from 0.75, level 2 from 0.875, ... up to termination at 0.99.
    EXPECT_GT(samples[0], 0u);
    EXPECT_GT(samples[1], 0u);
    EXPECT_GT(samples[2], 0u);
    for (int l = 7; l < gl::VrcRenderer::kMaxLodLevels; ++l) EXPECT_EQ(samples[l], 0u) << "level " << l;
}

TEST_F(GlTest, vrc_lod_images_stay_within_stated_psnr_of_exact_rendering) {
    const int w = 96, h = 72;
    const StyledLines lines = denseLines(0.3f);
    const Camera cam = cameraAt(3.0f);
    Scene peel;
    peel.image.width = w;
    peel.image.height = h;
    peel.render.transparency = Transparency::DepthPeeling;
    peel.output.aovDepth = peel.output.aovNormal = peel.output.aovId = false;
    const FrameImages ref = render(peel, lines, cam);
    const FrameImages off = render(lodScene(w, h, true, false, 1.0f, 0.5f), lines, cam);
    const FrameImages on = render(lodScene(w, h, true, true, 1.0f, 0.5f), lines, cam);
    const double offPeel = compareRgba(off.rgba, ref.rgba).psnr, onPeel = compareRgba(on.rgba, ref.rgba).psnr,
                 onOff = compareRgba(on.rgba, off.rgba).psnr;
    std::printf("PSNR dB: LoD off vs peel %.2f, LoD on vs peel %.2f, LoD on vs off %.2f\n", offPeel, onPeel, onOff);
    // Thin tubes (1-2 pixels) without anti-aliasing: VRC itself is ~23 dB from depth peeling here
    // (silhouette pixels; the GL tests of gl/vrc_renderer.h exclude them for exactness). The LoD
    // volume (from opacity 0.5 on) may cost at most 1.5 dB of that (measured 0.7).
    EXPECT_LT(onOff, 80.0);  // the LoD volume was used
    EXPECT_GT(onOff, 27.0);  // measured 30.2
    EXPECT_GT(onPeel, offPeel - 1.5);

    // A far view: footprint LoD on the opaque lines, against the exact opaque image.
    const Camera far = cameraAt(15.0f);
    const FrameImages farOff = render(lodScene(w, h, false, false, 1.0f, 0.5f), lines, far);
    const FrameImages farOn = render(lodScene(w, h, false, true, 1.0f, 0.5f), lines, far);
    const double farPsnr = compareRgba(farOn.rgba, farOff.rgba).psnr;
    std::printf("PSNR dB: far opaque LoD on vs off %.2f\n", farPsnr);
    // Sub-pixel tubes: the exact image is aliased, the volume gives their mean coverage.
    EXPECT_LT(farPsnr, 80.0);
    EXPECT_GT(farPsnr, 20.0);  // measured 23.5
}

}  // namespace
}  // namespace tc::test
