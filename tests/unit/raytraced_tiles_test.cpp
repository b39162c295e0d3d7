// rt/primary_rays.h pixelBlockMisses: a pixel block it calls a miss has no sample ray (any jitter
// within the pixels) that meets the box, for perspective and orthographic cameras, full images
// and windows of a larger image; and it is not vacuous (blocks away from the box's image miss).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/camera.h"
#include "core/tiling.h"
#include "rt/primary_rays.h"

namespace tc::test {
namespace {

bool rayMeetsBox(const Ray& r, const rt::SceneBounds& b) {
    float t0 = 0.0f, t1 = 1e30f;
    for (int a = 0; a < 3; ++a) {
        const float inv = 1.0f / r.dir[a];
        float lo = (b.lo[a] - r.origin[a]) * inv, hi = (b.hi[a] - r.origin[a]) * inv;
        if (lo > hi) std::swap(lo, hi);
        t0 = std::max(t0, lo);
        t1 = std::min(t1, hi);
    }
    return t0 <= t1;
}

void check(const Camera& cam, const ImageWindow& window, int width, int height, std::uint32_t seed) {
    const PixelRays rays(cam, fullWidthOf(window, width), fullHeightOf(window, height));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), size(0.01f, 0.4f);
    int misses = 0, blocks = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const glm::vec3 c(u(rng), u(rng), u(rng)), half(size(rng), size(rng), size(rng));
        const rt::SceneBounds box{c - half, c + half};
        for (int y0 = 0; y0 < height; y0 += 8)
            for (int x0 = 0; x0 < width; x0 += 8) {
                const int w = std::min(8, width - x0), h = std::min(8, height - y0);
                ++blocks;
                if (!rt::pixelBlockMisses(rays, window, x0, y0, w, h, box)) continue;
                ++misses;
                // Every sample position of the block's pixels: centres and corners (jitter <= 0.5).
                for (int y = 2 * y0; y <= 2 * (y0 + h - 1) + 2; ++y)
                    for (int x = 2 * x0; x <= 2 * (x0 + w - 1) + 2; ++x) {
                        const glm::vec2 p = fullImagePixel(window, 0.5f * float(x) - 0.5f, 0.5f * float(y) - 0.5f);
                        ASSERT_FALSE(rayMeetsBox(rays(p.x, p.y), box))
                            << "block (" << x0 << ", " << y0 << ") sample " << x << ", " << y << " trial " << trial;
                    }
            }
    }
    EXPECT_GT(misses, blocks / 4) << "of " << blocks;
    EXPECT_LT(misses, blocks) << "of " << blocks;
}

TEST(PixelBlockMisses, no_sample_ray_of_a_missed_block_meets_the_box_perspective) {
    Camera cam;
    cam.eye = {0.4f, -2.5f, 1.2f};
    cam.target = {0.0f, 0.1f, 0.0f};
    cam.up = {0, 0, 1};
    cam.fovYDeg = 40.0f;
    check(cam, ImageWindow{}, 61, 43, 1);
    // A tile of a larger image, with a sample offset.
    ImageWindow window;
    window.fullWidth = 160;
    window.fullHeight = 120;
    window.x = 50;
    window.y = 30;
    window.jitter = {0.37f, -0.42f};
    check(cam, window, 48, 40, 2);
}

TEST(PixelBlockMisses, no_sample_ray_of_a_missed_block_meets_the_box_orthographic) {
    Camera cam;
    cam.eye = {2.0f, 1.0f, 2.5f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 2.5f;
    check(cam, ImageWindow{}, 57, 40, 3);
}

TEST(PixelBlockMisses, an_empty_scene_misses_everywhere_and_a_box_around_the_eye_nowhere) {
    Camera cam;
    const PixelRays rays(cam, 32, 32);
    rt::SceneBounds empty{glm::vec3(1.0f), glm::vec3(-1.0f)};
    EXPECT_TRUE(rt::pixelBlockMisses(rays, ImageWindow{}, 0, 0, 8, 8, empty));
    rt::SceneBounds around{cam.eye - glm::vec3(0.1f), cam.eye + glm::vec3(0.1f)};
    for (int y0 = 0; y0 < 32; y0 += 8)
        for (int x0 = 0; x0 < 32; x0 += 8)
            EXPECT_FALSE(rt::pixelBlockMisses(rays, ImageWindow{}, x0, y0, 8, 8, around));
}

}  // namespace
}  // namespace tc::test
