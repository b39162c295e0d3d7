// Tiles and sub-pixel samples (core/tiling.h): tile grids cover the image exactly once on even
// edges, a tile's rays are bit-for-bit the full image's, the NDC map puts full-image geometry on
// the target's pixels, the budget planner picks the fewest tiles that fit (and fails with the key
// when none does), the R2 samples estimate pixel coverage, and image.tiles / image.samples parse.
#include "core/tiling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>

#include "core/error.h"
#include "core/scene.h"

namespace tc {
namespace {

bool sameBits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

void expectGridCoversOnce(int w, int h, int nx, int ny) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " in " + std::to_string(nx) + "x" + std::to_string(ny));
    const std::vector<TileRect> tiles = tileGrid(w, h, nx, ny);
    ASSERT_EQ(tiles.size(), std::size_t(nx) * ny);
    std::vector<int> hits(std::size_t(w) * h, 0);
    int minW = w, maxW = 0, minH = h, maxH = 0;
    for (const TileRect& t : tiles) {
        ASSERT_GT(t.width, 0);
        ASSERT_GT(t.height, 0);
        // Even edges from the left and from the bottom (GL), except the image's own far edges.
        EXPECT_EQ(t.x % 2, 0);
        EXPECT_EQ((h - t.y - t.height) % 2, 0);
        minW = std::min(minW, t.width), maxW = std::max(maxW, t.width);
        minH = std::min(minH, t.height), maxH = std::max(maxH, t.height);
        for (int y = t.y; y < t.y + t.height; ++y)
            for (int x = t.x; x < t.x + t.width; ++x) ++hits[std::size_t(y) * w + x];
    }
    EXPECT_TRUE(std::all_of(hits.begin(), hits.end(), [](int c) { return c == 1; }));
    EXPECT_LE(maxW - minW, 3);
    EXPECT_LE(maxH - minH, 3);
    EXPECT_EQ(tiles.front().x, 0);
    EXPECT_EQ(tiles.front().y, 0);  // row-major from the top-left
}

TEST(Tiling, tile_grids_cover_every_pixel_once_on_even_edges) {
    expectGridCoversOnce(96, 64, 3, 2);
    expectGridCoversOnce(97, 63, 3, 2);  // odd sizes: uneven tiles
    expectGridCoversOnce(64, 48, 1, 1);
    expectGridCoversOnce(5, 3, 2, 1);
    expectGridCoversOnce(1000, 777, 7, 5);
    const std::vector<TileRect> t = tileGrid(97, 63, 3, 2);
    EXPECT_EQ(t[2].width, 33);   // the last column takes the odd pixel
    EXPECT_EQ(t[0].height, 33);  // the top row: GL rows 30..62
    EXPECT_EQ(t[3].height, 30);
}

Camera testCamera(Projection p) {
    Camera c;
    c.eye = {0.3f, -0.2f, 3.1f};
    c.target = {0.05f, 0.1f, 0.0f};
    c.up = {0.1f, 1.0f, 0.0f};
    c.fovYDeg = 37.0f;
    c.projection = p;
    c.orthoHeight = 2.3f;
    return c;
}

TEST(Tiling, tile_rays_are_bit_identical_to_the_full_images) {
    for (Projection p : {Projection::Perspective, Projection::Orthographic}) {
        const Camera cam = testCamera(p);
        const int w = 97, h = 63;
        for (const TileRect& t : tileGrid(w, h, 3, 2)) {
            const ImageWindow win{w, h, t.x, t.y, {0.0f, 0.0f}};
            for (int py = 0; py < t.height; py += 5)
                for (int px = 0; px < t.width; px += 3) {
                    const Ray a = windowPixelRay(cam, win, t.width, t.height, px, py);
                    const Ray b = pixelRay(cam, w, h, float(t.x + px), float(t.y + py));
                    for (int k = 0; k < 3; ++k) {
                        ASSERT_TRUE(sameBits(a.origin[k], b.origin[k]));
                        ASSERT_TRUE(sameBits(a.dir[k], b.dir[k]));
                    }
                }
        }
        // A full window is tc::pixelRay itself.
        const Ray a = windowPixelRay(cam, ImageWindow{}, w, h, 10, 20), b = pixelRay(cam, w, h, 10.0f, 20.0f);
        EXPECT_TRUE(sameBits(a.dir.x, b.dir.x) && sameBits(a.dir.y, b.dir.y) && sameBits(a.dir.z, b.dir.z));
    }
}

TEST(Tiling, ndc_map_puts_full_image_samples_on_target_pixel_centres) {
    // Full window: exactly the identity, so untiled rasterization is unchanged.
    const glm::vec4 id = ndcToTarget(ImageWindow{}, 640, 480);
    EXPECT_EQ(id, glm::vec4(1.0f, 1.0f, 0.0f, 0.0f));
    EXPECT_EQ(glWindowOffset(ImageWindow{}, 640, 480), glm::vec2(0.0f));

    const int W = 97, H = 63;
    const glm::vec2 jitter{0.3125f, -0.1875f};
    for (const TileRect& t : tileGrid(W, H, 3, 2)) {
        const ImageWindow win{W, H, t.x, t.y, jitter};
        const glm::vec4 m = ndcToTarget(win, t.width, t.height);
        const glm::vec2 off = glWindowOffset(win, t.width, t.height);
        for (int py : {0, t.height - 1})
            for (int px : {0, t.width - 1}) {
                // The sample of target pixel (px, py), in full-image GL window coordinates...
                const glm::vec2 full = fullImagePixel(win, float(px), float(py)) + 0.5f;
                const glm::vec2 window{full.x, float(H) - full.y};
                const glm::vec2 ndc = 2.0f * window / glm::vec2(W, H) - 1.0f;
                // ...lands on that pixel's centre in the target, GL rows counted from the bottom.
                const glm::vec2 tndc = ndc * glm::vec2(m.x, m.y) + glm::vec2(m.z, m.w);
                const glm::vec2 twin = (tndc * 0.5f + 0.5f) * glm::vec2(t.width, t.height);
                EXPECT_NEAR(twin.x, px + 0.5f, 1e-4f);
                EXPECT_NEAR(twin.y, (t.height - 1 - py) + 0.5f, 1e-4f);
                // The shader's ray position gl_FragCoord + uPixelOffset is the same sample.
                EXPECT_NEAR(px + 0.5f + off.x, window.x, 1e-4f);
                EXPECT_NEAR((t.height - 1 - py) + 0.5f + off.y, window.y, 1e-4f);
            }
    }
}

TEST(Tiling, budget_planner_picks_the_fewest_tiles_that_fit) {
    // Fits: one tile, not automatic.
    TilePlan one = planTiles(640, 480, 0, 0, 100, 640 * 480 * 100, "x");
    EXPECT_EQ(one.tiles.size(), 1u);
    EXPECT_FALSE(one.automatic);
    // 16384^2 k-buffer (k=8, AOVs, culling: 118 B/px) under 512 MB.
    const std::size_t bpp = 16 + 64 + 36 + 2, budget = std::size_t(512) << 20;
    TilePlan big = planTiles(16384, 16384, 0, 0, bpp, budget, "kbuffer with k=8");
    EXPECT_TRUE(big.automatic);
    EXPECT_LE(big.largestTileBytes, budget);
    const std::size_t needed = (std::size_t(16384) * 16384 * bpp + budget - 1) / budget;
    EXPECT_GE(big.tiles.size(), needed);
    // No grid with fewer tiles fits (brute force over the grids with fewer tiles).
    for (int ny = 1; ny <= 256; ++ny)
        for (int nx = 1; nx * ny < int(big.tiles.size()) && nx <= 256; ++nx) {
            std::size_t largest = 0;
            for (const TileRect& t : tileGrid(16384, 16384, nx, ny)) largest = std::max(largest, t.pixelCount() * bpp);
            EXPECT_GT(largest, budget) << nx << "x" << ny;
        }
    // An explicit grid is taken as given.
    TilePlan given = planTiles(96, 64, 3, 2, 1000, 1, "x");
    EXPECT_EQ(given.nx, 3);
    EXPECT_EQ(given.ny, 2);
    EXPECT_FALSE(given.automatic);
}

TEST(Tiling, budget_below_the_smallest_tile_is_an_input_error_naming_the_key) {
    try {
        planTiles(4096, 4096, 0, 0, 300, std::size_t(1) << 20, "kbuffer with k=16");
        FAIL() << "no error";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("render.memory_budget_mb: kbuffer with k=16 needs ", 0), 0u) << msg;
        EXPECT_NE(msg.find("smallest tile (64x64)"), std::string::npos) << msg;
        EXPECT_NE(msg.find("budget of 1 MB"), std::string::npos) << msg;
    }
}

TEST(Tiling, sample_sets_stay_in_the_pixel_one_sample_is_the_centre) {
    EXPECT_EQ(sampleOffsets(1), std::vector<glm::vec2>{glm::vec2(0.0f)});
    for (int n : {2, 4, 16, 64, 1000}) {
        const std::vector<glm::vec2> s = sampleOffsets(n);
        ASSERT_EQ(s.size(), std::size_t(n));
        for (const glm::vec2& o : s) {
            EXPECT_GE(o.x, -0.5f);
            EXPECT_LE(o.x, 0.5f);
            EXPECT_GE(o.y, -0.5f);
            EXPECT_LE(o.y, 0.5f);
            // Multiples of 1/256: integer pixel + offset is exact in float below 65536.
            EXPECT_EQ(o.x * 256.0f, std::round(o.x * 256.0f));
            EXPECT_EQ(o.y * 256.0f, std::round(o.y * 256.0f));
            EXPECT_EQ((40000.0f + o.x) - 40000.0f, o.x);
        }
        const glm::vec2 c = s[nearestToCentre(s)];
        for (const glm::vec2& o : s) EXPECT_LE(glm::dot(c, c), glm::dot(o, o));
    }
    // One sample per column stratum (x stratified): 16 distinct x in 16 strata.
    const std::vector<glm::vec2> s = sampleOffsets(16);
    for (int i = 0; i < 16; ++i) EXPECT_EQ(s[std::size_t(i)].x, (i + 0.5f) / 16.0f - 0.5f);
}

// The fraction of 16 samples on one side of a straight edge through the pixel against the
// exact area (by 512 x 512 midpoint sampling), over edges of every angle and offset: this is the
// tolerance the GPU anti-aliasing test (tests/gl/tiling_test.cpp) states (0.13, mean 0.04).
TEST(Tiling, sixteen_samples_estimate_edge_coverage_within_an_eighth) {
    const std::vector<glm::vec2> s = sampleOffsets(16);
    double worst = 0, sum = 0;
    int count = 0;
    for (int a = 0; a < 72; ++a) {
        const double ang = a * 2.5 * M_PI / 180.0;
        const glm::dvec2 n{std::cos(ang), std::sin(ang)};
        for (int k = -20; k <= 20; ++k) {
            const double c = k / 40.0;  // edge: dot(n, p) < c, p in [-0.5, 0.5)^2
            int inside = 0;
            for (const glm::vec2& o : s) inside += glm::dot(n, glm::dvec2(o)) < c;
            const int g = 512;
            long exact = 0;
            for (int y = 0; y < g; ++y)
                for (int x = 0; x < g; ++x)
                    exact += glm::dot(n, glm::dvec2((x + 0.5) / g - 0.5, (y + 0.5) / g - 0.5)) < c;
            const double err = std::abs(inside / 16.0 - double(exact) / (g * g));
            worst = std::max(worst, err);
            sum += err;
            ++count;
        }
    }
    std::printf("[ measured ] 16 samples vs exact edge coverage: max error %.4f, mean %.4f\n", worst, sum / count);
    EXPECT_LE(worst, 0.13);
    EXPECT_LE(sum / count, 0.04);
}

TEST(Tiling, image_tiles_and_samples_parse_and_validate) {
    using nlohmann::json;
    auto parse = [](const char* image) {
        json doc = json::parse(R"({"dataset": {"generate": "tornado"}})");
        doc["image"] = json::parse(image);
        return parseScene(doc, "scene.json");
    };
    auto error = [&](const char* image) -> std::string {
        try {
            parse(image);
        } catch (const InputError& e) {
            return e.what();
        }
        return "<no error>";
    };
    Scene a = parse(R"({"width": 96, "height": 64, "tiles": [3, 2], "samples": 16})");
    EXPECT_EQ(a.image.tilesX, 3);
    EXPECT_EQ(a.image.tilesY, 2);
    EXPECT_EQ(a.image.samples, 16);
    Scene b = parse(R"({"tiles": "auto"})");
    EXPECT_EQ(b.image.tilesX, 0);
    EXPECT_EQ(b.image.samples, 1);
    EXPECT_EQ(error(R"({"width": 96, "height": 64, "tiles": [49, 2]})"),
              "scene.json: image.tiles: expected \"auto\" or [nx, ny] with integers 1..48 and 1..32 (at most "
              "width/2 x height/2), got [49,2]");
    EXPECT_NE(error(R"({"tiles": [2]})").find("image.tiles: expected"), std::string::npos);
    EXPECT_NE(error(R"({"samples": 0})").find("image.samples"), std::string::npos);
    // Opacity optimization takes image.samples itself (one solve per frame), not tiles.
    json samples = json::parse(R"({"dataset": {"generate": "tornado"}, "image": {"samples": 4},
                                   "render": {"transparency": "opacity_optimization"}})");
    EXPECT_EQ(parseScene(samples, "scene.json").image.samples, 4);
    json doc = json::parse(R"({"dataset": {"generate": "tornado"}, "image": {"tiles": [2, 2]},
                               "render": {"transparency": "opacity_optimization"}})");
    try {
        parseScene(doc, "scene.json");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(
            std::string(e.what()).rfind("scene.json: image.tiles: render.transparency \"opacity_optimization\"", 0), 0u)
            << e.what();
    }
}

}  // namespace
}  // namespace tc
