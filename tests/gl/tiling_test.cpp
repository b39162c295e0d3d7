// Tiled and anti-aliased rendering (core/tiling.h, core/tiled_technique.h, gl/view_window.h):
// - tiled == untiled: a frame rendered as 3 x 2 tiles of uneven size (97 x 63) equals the untiled
//   frame in every channel (colour, depth, normal, id, AO), bit for bit, for the rasterized
//   opaque path (culling and AO on), the k-buffer (culling and AO on), depth peeling, spheres
//   and voxel ray casting, perspective and orthographic; so do 4-sample frames tiled vs untiled;
// - image.samples = 16 on a tilted opaque edge gives each pixel the fraction of the band that
//   covers it (analytic), within the 16-sample estimate's error bound of
//   tests/unit/tiling_test.cpp (0.13 per pixel, 0.04 mean);
// - depth, normal and id of an anti-aliased frame are those of its sample nearest the centre:
//   exactly a single-sample frame at that sub-pixel position, never a blend of surfaces.
#include "core/tiling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/scene.h"
#include "core/technique.h"
#include "core/tiled_technique.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

Camera lookAt(glm::vec3 eye, Projection projection) {
    Camera cam;
    cam.eye = eye;
    cam.target = {0.02f, -0.03f, 0.0f};
    cam.up = {0, 1, 0};
    cam.fovYDeg = 40.0f;
    cam.projection = projection;
    cam.orthoHeight = 1.8f;
    return cam;
}

struct Rendered {
    FrameImages images;
    std::uint64_t culled = 0;
};

// A fresh technique for `scene`, wrapped in nx x ny tiles and `samples` samples (1 x 1 and one
// sample: the technique itself, the untiled path).
Rendered render(const Scene& scene, const StyledLines& lines, const Camera& cam, int nx, int ny, int samples) {
    const int w = scene.image.width, h = scene.image.height;
    auto technique =
        wrapInTiles(gl::createTechnique(scene, lines), planTiles(w, h, nx, ny, 0, 0, ""), samples, KeptAovs{});
    Rendered r;
    gl::StageTimer timer;
    technique->render(tc::FrameSetup{0, cam, w, h}, r.images, timer);
    for (const tc::StageTime& t : timer.collect())
        if (t.stage == "culling") r.culled += t.items;
    return r;
}

template <class T>
std::size_t countDifferent(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return std::max(a.size(), b.size());
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i) n += !(a[i] == b[i]);
    return n;
}

void expectIdentical(const FrameImages& a, const FrameImages& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    EXPECT_EQ(countDifferent(a.rgba, b.rgba), 0u);
    EXPECT_EQ(countDifferent(a.depth, b.depth), 0u);
    EXPECT_EQ(countDifferent(a.normal, b.normal), 0u);
    EXPECT_EQ(countDifferent(a.id, b.id), 0u);
    EXPECT_EQ(countDifferent(a.ao, b.ao), 0u);
}

std::size_t coveredPixels(const FrameImages& f) {
    std::size_t n = 0;
    for (std::size_t i = 3; i < f.rgba.size(); i += 4) n += f.rgba[i] > 0.0f;
    return n;
}

// Dense tubes around the origin: several layers deep, so culling has work and AO has shadows.
StyledLines denseTubes(float alpha) {
    RandomSceneOptions o;
    o.polylines = 120;
    o.minSegments = 3;
    o.maxSegments = 6;
    o.radiusMin = 0.04f;
    o.radiusRatio = 2.0f;
    o.stepMin = 0.1f;
    o.stepMax = 0.25f;
    o.maxBendDeg = 50.0f;
    o.extent = 0.35f;
    StyledLines lines = randomLineScene(17, o);
    for (glm::vec4& c : lines.color) c.w = alpha;
    return lines;
}

Scene smallScene(RenderTechnique technique, Transparency transparency) {
    Scene s;
    s.image.width = 97;
    s.image.height = 63;
    s.render.technique = technique;
    s.render.transparency = transparency;
    s.render.kbufferK = 4;
    s.render.ao.enabled = true;
    s.render.ao.resolution = 48;
    s.render.culling.enabled = true;
    s.render.culling.slices = 4;
    s.render.culling.opacityThreshold = 0.5f;
    s.render.vrc.resolution = 24;
    return s;
}

void expectTiledEqualsUntiled(const Scene& scene, const StyledLines& lines, bool expectCulling) {
    for (Projection p : {Projection::Perspective, Projection::Orthographic}) {
        SCOPED_TRACE(p == Projection::Perspective ? "perspective" : "orthographic");
        const Camera cam = lookAt({0.4f, 0.5f, 2.2f}, p);
        const Rendered full = render(scene, lines, cam, 1, 1, 1);
        const Rendered tiled = render(scene, lines, cam, 3, 2, 1);
        ASSERT_GT(coveredPixels(full.images), 500u);
        ASSERT_LT(coveredPixels(full.images), full.images.pixelCount());
        if (scene.render.ao.enabled && scene.render.transparency == Transparency::Opaque &&
            scene.render.technique == RenderTechnique::Rasterized) {
            ASSERT_FALSE(full.images.ao.empty());
        }
        // Billboard-level culls are what the counter sees; the orthographic k-buffer view culls
        // per fragment only, so the count is asserted on the perspective view.
        if (expectCulling && p == Projection::Perspective) {
            EXPECT_GT(full.culled, 0u) << "culling did nothing: the comparison would not test it";
        }
        expectIdentical(tiled.images, full.images);
    }
}

TEST_F(GlTest, tiled_opaque_rasterized_with_culling_and_ao_equals_untiled) {
    expectTiledEqualsUntiled(smallScene(RenderTechnique::Rasterized, Transparency::Opaque), denseTubes(1.0f), true);
}

TEST_F(GlTest, tiled_kbuffer_with_culling_and_ao_equals_untiled) {
    expectTiledEqualsUntiled(smallScene(RenderTechnique::Rasterized, Transparency::KBuffer), denseTubes(0.9f), true);
}

TEST_F(GlTest, tiled_depth_peeling_and_object_order_equal_untiled) {
    Scene peel = smallScene(RenderTechnique::Rasterized, Transparency::DepthPeeling);
    peel.render.culling.enabled = false;
    expectTiledEqualsUntiled(peel, denseTubes(0.5f), false);
    expectTiledEqualsUntiled(smallScene(RenderTechnique::Rasterized, Transparency::ObjectOrder), denseTubes(0.7f),
                             true);
}

TEST_F(GlTest, tiled_spheres_and_voxel_raycast_equal_untiled) {
    expectTiledEqualsUntiled(smallScene(RenderTechnique::Spheres, Transparency::Opaque), denseTubes(1.0f), false);
    expectTiledEqualsUntiled(smallScene(RenderTechnique::Spheres, Transparency::ObjectOrder), denseTubes(0.6f), false);
    expectTiledEqualsUntiled(smallScene(RenderTechnique::VoxelRaycast, Transparency::Opaque), denseTubes(1.0f), false);
    expectTiledEqualsUntiled(smallScene(RenderTechnique::VoxelRaycast, Transparency::KBuffer), denseTubes(0.6f), false);
}

TEST_F(GlTest, tiled_samples_equal_untiled_samples_and_one_tile_one_sample_is_the_technique) {
    const Scene scene = smallScene(RenderTechnique::Rasterized, Transparency::KBuffer);
    const StyledLines lines = denseTubes(0.7f);
    const Camera cam = lookAt({0.4f, 0.5f, 2.2f}, Projection::Perspective);
    expectIdentical(render(scene, lines, cam, 3, 2, 4).images, render(scene, lines, cam, 1, 1, 4).images);
    // The stitching path itself with one tile and one sample changes nothing.
    TiledTechnique wrapped(gl::createTechnique(scene, lines), planTiles(97, 63, 1, 1, 0, 0, ""), 1, KeptAovs{});
    FrameImages viaWrapper;
    gl::StageTimer timer;
    wrapped.render(tc::FrameSetup{0, cam, 97, 63}, viaWrapper, timer);
    timer.collect();
    expectIdentical(viaWrapper, render(scene, lines, cam, 1, 1, 1).images);
}

// One long opaque tube across a 64 x 64 orthographic view, its axis tilted by 27 degrees in the
// image plane: its silhouette is the band |distance to the axis| <= r, two straight edges.
struct EdgeScene {
    StyledLines lines;
    Camera camera;
    glm::vec2 dir{std::cos(glm::radians(27.0f)), std::sin(glm::radians(27.0f))};
    glm::vec2 origin{0.05f, -0.11f};
    float radius = 0.37f;
};

EdgeScene edgeScene() {
    EdgeScene e;
    const glm::vec2 a = e.origin - 4.0f * e.dir, b = e.origin + 4.0f * e.dir;
    e.lines = makeStyledLines({{{{a.x, a.y, 0.0f}, e.radius, {0.9f, 0.6f, 0.3f, 1.0f}},
                                {{b.x, b.y, 0.0f}, e.radius, {0.9f, 0.6f, 0.3f, 1.0f}}}});
    e.camera.eye = {0, 0, 3};
    e.camera.target = {0, 0, 0};
    e.camera.up = {0, 1, 0};
    e.camera.projection = Projection::Orthographic;
    e.camera.orthoHeight = 2.0f;
    return e;
}

// Fraction of pixel (px, py) (row 0 = top) of a 64 x 64 image covering [-1, 1]^2 inside the band,
// by 128 x 128 midpoint sampling (error < 1 / 128 per edge crossing).
float bandCoverage(const EdgeScene& e, int px, int py) {
    const float s = 2.0f / 64.0f;
    const glm::vec2 n{-e.dir.y, e.dir.x};
    const int g = 128;
    int inside = 0;
    for (int j = 0; j < g; ++j)
        for (int i = 0; i < g; ++i) {
            const glm::vec2 p{-1.0f + (px + (i + 0.5f) / g) * s, 1.0f - (py + (j + 0.5f) / g) * s};
            inside += std::abs(glm::dot(p - e.origin, n)) <= e.radius;
        }
    return float(inside) / float(g * g);
}

TEST_F(GlTest, sixteen_samples_give_tilted_edge_pixels_their_analytic_coverage) {
    const EdgeScene e = edgeScene();
    Scene scene;
    scene.image.width = scene.image.height = 64;
    const FrameImages one = render(scene, e.lines, e.camera, 1, 1, 1).images;
    const FrameImages aa = render(scene, e.lines, e.camera, 1, 1, 16).images;
    std::size_t partial = 0, partialOne = 0;
    double worst = 0, sum = 0;
    for (int py = 0; py < 64; ++py)
        for (int px = 0; px < 64; ++px) {
            const float cov = bandCoverage(e, px, py);
            const float alpha = aa.rgba[4 * (std::size_t(py) * 64 + px) + 3];
            const float alphaOne = one.rgba[4 * (std::size_t(py) * 64 + px) + 3];
            partialOne += alphaOne > 0.0f && alphaOne < 1.0f;
            if (cov == 0.0f || cov == 1.0f) {
                // Far from both edges every sample agrees.
                EXPECT_EQ(alpha, cov) << px << "," << py;
                continue;
            }
            const double err = std::abs(double(alpha) - cov);
            worst = std::max(worst, err);
            sum += err;
            ++partial;
            EXPECT_LE(err, 0.13 + 1.0 / 64) << "pixel " << px << "," << py << " coverage " << cov;
            // Alpha is a whole number of 16ths: the fraction of samples that hit.
            EXPECT_EQ(alpha * 16.0f, std::round(alpha * 16.0f));
        }
    std::printf("[ measured ] 16 samples on %zu edge pixels: max |alpha - coverage| %.4f, mean %.4f\n", partial, worst,
                partial ? sum / double(partial) : 0.0);
    EXPECT_GE(partial, 100u);  // two edges across 64 columns
    EXPECT_LE(sum / double(partial), 0.045);
    EXPECT_EQ(partialOne, 0u);  // one sample per pixel: no intermediate coverage at all
}

TEST_F(GlTest, anti_aliased_depth_normal_and_id_are_the_nearest_samples) {
    Scene scene = smallScene(RenderTechnique::Rasterized, Transparency::Opaque);
    const StyledLines lines = denseTubes(1.0f);
    const Camera cam = lookAt({0.4f, 0.5f, 2.2f}, Projection::Perspective);
    // One sample at the nearest offset, over the whole image: a window of the full size.
    const std::vector<glm::vec2> offsets = sampleOffsets(8);
    const ImageWindow nearest{97, 63, 0, 0, offsets[nearestToCentre(offsets)]};
    ASSERT_NE(nearest.jitter, glm::vec2(0.0f));
    FrameImages one;
    gl::StageTimer timer;
    gl::createTechnique(scene, lines)->render(tc::FrameSetup{0, cam, 97, 63, nearest}, one, timer);
    timer.collect();
    const FrameImages aa = render(scene, lines, cam, 3, 2, 8).images;
    EXPECT_EQ(countDifferent(aa.depth, one.depth), 0u);
    EXPECT_EQ(countDifferent(aa.normal, one.normal), 0u);
    EXPECT_EQ(countDifferent(aa.id, one.id), 0u);
    // ... while colour did change at silhouettes (the samples are not all at the centre).
    std::size_t changed = 0;
    for (std::size_t i = 3; i < aa.rgba.size(); i += 4) changed += aa.rgba[i] != one.rgba[i];
    EXPECT_GT(changed, 100u);
}

}  // namespace
}  // namespace tc::test
