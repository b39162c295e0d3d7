// rt/tile_cover.h: the tiles a frame's tubes may show in. Conservative against brute force (every
// pixel whose sample ray meets a rounded cone lies in a marked tile, for perspective and
// orthographic cameras, image windows with sub-pixel jitter and partial tiles), useful (a ring seen
// face-on leaves its centre and the image corners unmarked), and "unknown" (empty) when the data
// reaches the eye.
#include "rt/tile_cover.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/rounded_cone.h"
#include "core/tiling.h"
#include "rt/primary_rays.h"

namespace tc {
namespace {

// Polylines of `points` vertices each (radius per vertex), contiguous, segments (v, v + 1).
StyledLines linesOf(const std::vector<std::vector<glm::vec4>>& polylines) {
    StyledLines l;
    for (std::size_t p = 0; p < polylines.size(); ++p) {
        const std::uint32_t begin = std::uint32_t(l.positionRadius.size());
        for (const glm::vec4& v : polylines[p]) {
            l.positionRadius.push_back(v);
            l.color.push_back(glm::vec4(1.0f));
            l.polylineId.push_back(std::uint32_t(p));
            l.flags.push_back(0);
            l.bounds.extend(glm::vec3(v), v.w);
            l.maxRadius = std::max(l.maxRadius, v.w);
        }
        for (std::uint32_t k = 0; k + 1 < polylines[p].size(); ++k) {
            l.segmentVertices.push_back(begin + k);
            l.segmentVertices.push_back(begin + k + 1);
        }
    }
    return l;
}

StyledLines randomLines(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-1.0f, 1.0f), rad(0.005f, 0.08f), step(-0.3f, 0.3f);
    std::vector<std::vector<glm::vec4>> polylines(12);
    for (auto& pl : polylines) {
        glm::vec3 p(pos(rng), pos(rng), 0.5f * pos(rng));
        for (int k = 0; k < 6; ++k) {
            pl.push_back(glm::vec4(p, rad(rng)));
            p += glm::vec3(step(rng), step(rng), step(rng));
        }
    }
    return linesOf(polylines);
}

// Whether the sample ray of target pixel (px, py) meets any rounded cone at t > 0.
bool rayMeetsTubes(const StyledLines& lines, const Ray& ray) {
    for (std::size_t s = 0; s < lines.segmentCount(); ++s) {
        const glm::vec4& a = lines.positionRadius[lines.segmentVertices[2 * s]];
        const glm::vec4& b = lines.positionRadius[lines.segmentVertices[2 * s + 1]];
        if (firstSurfaceHit(ray, {glm::vec3(a), a.w, glm::vec3(b), b.w})) return true;
    }
    return false;
}

// Pixels hit by brute force, and how many of them lie in tiles the cover leaves out.
struct Check {
    int hitPixels = 0, missed = 0, markedTiles = 0, tiles = 0;
};

Check check(const StyledLines& lines, const rt::TileCover& cover, const Camera& cam, const ImageWindow& window, int w,
            int h) {
    const std::vector<std::uint8_t> mask = cover.tiles(cam, window, w, h, rt::kTile);
    const int tilesX = (w + rt::kTile - 1) / rt::kTile, tilesY = (h + rt::kTile - 1) / rt::kTile;
    Check c;
    c.tiles = tilesX * tilesY;
    EXPECT_EQ(mask.size(), std::size_t(c.tiles));
    if (mask.size() != std::size_t(c.tiles)) return c;
    for (std::uint8_t m : mask) c.markedTiles += m;
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            if (!rayMeetsTubes(lines, windowPixelRay(cam, window, w, h, px, py))) continue;
            ++c.hitPixels;
            if (!mask[std::size_t((py / rt::kTile) * tilesX + px / rt::kTile)]) ++c.missed;
        }
    return c;
}

Camera camera(glm::vec3 eye, Projection projection) {
    Camera cam;
    cam.eye = eye;
    cam.target = {0.1f, -0.05f, 0.0f};
    cam.up = {0.0f, 0.0f, 1.0f};
    cam.fovYDeg = 30.0f;
    cam.projection = projection;
    cam.orthoHeight = 2.6f;
    return cam;
}

TEST(TileCover, every_pixel_whose_ray_meets_a_tube_lies_in_a_marked_tile) {
    int hitPixels = 0, unmarked = 0, tiles = 0;
    for (unsigned seed : {1u, 2u, 3u}) {
        const StyledLines lines = randomLines(seed);
        // A coarse grid too: cells far larger than the tubes.
        for (int cells : {4, 32}) {
            const rt::TileCover cover(lines, cells);
            for (Projection projection : {Projection::Perspective, Projection::Orthographic})
                for (glm::vec3 eye : {glm::vec3(0.3f, -3.5f, 1.2f), glm::vec3(-2.0f, 2.5f, -2.5f)}) {
                    const Camera cam = camera(eye, projection);
                    // The whole image (100 x 60: partial tiles at both edges), and a 45 x 37
                    // window of a 4x larger image with jitter, as tiled or supersampled renders.
                    const Check full = check(lines, cover, cam, {}, 100, 60);
                    const ImageWindow window{400, 240, 170, 93, {0.37f, -0.41f}};
                    const Check part = check(lines, cover, cam, window, 45, 37);
                    for (const Check& c : {full, part}) {
                        EXPECT_EQ(c.missed, 0) << "seed " << seed << " cells " << cells;
                        hitPixels += c.hitPixels;
                        unmarked += c.tiles - c.markedTiles;
                        tiles += c.tiles;
                    }
                }
        }
    }
    EXPECT_GT(hitPixels, 10000);  // the test sees tubes
    EXPECT_GT(unmarked, tiles / 20) << "the cover never leaves a tile out";
}

TEST(TileCover, a_ring_seen_face_on_leaves_its_centre_and_the_corners_out) {
    std::vector<glm::vec4> ring;
    for (int k = 0; k <= 64; ++k) {
        const float a = 6.2831853f * float(k) / 64.0f;
        ring.push_back(glm::vec4(std::cos(a), std::sin(a), 0.0f, 0.03f));
    }
    const StyledLines lines = linesOf({ring});
    const rt::TileCover cover(lines);
    Camera cam;
    cam.eye = {0.0f, 0.0f, 4.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.up = {0.0f, 1.0f, 0.0f};
    cam.fovYDeg = 40.0f;
    const int w = 160, h = 160, tilesX = w / rt::kTile;
    const std::vector<std::uint8_t> mask = cover.tiles(cam, {}, w, h, rt::kTile);
    ASSERT_EQ(mask.size(), std::size_t(tilesX * tilesX));
    EXPECT_EQ(mask[std::size_t((tilesX / 2) * tilesX + tilesX / 2)], 0);  // the hole
    EXPECT_EQ(mask[0], 0);                                                // a corner
    EXPECT_EQ(mask.back(), 0);
    // The ring's top: pixel row of y = 1 at depth 4 is (1 - 1 / (4 tan 20 deg)) * 80.
    const int ringRow = int((1.0f - 1.0f / (4.0f * std::tan(glm::radians(20.0f)))) * 80.0f);
    EXPECT_EQ(mask[std::size_t((ringRow / rt::kTile) * tilesX + tilesX / 2)], 1);
    const Check c = check(lines, cover, cam, {}, w, h);
    EXPECT_EQ(c.missed, 0);
    EXPECT_LT(c.markedTiles, c.tiles / 2);
}

TEST(TileCover, holds_every_tube_whatever_bounds_the_lines_carry) {
    // StyledLines::bounds may be of other data (a union over ranks or frames, or stale): the grid
    // is built from the segments.
    StyledLines lines = randomLines(5);
    lines.bounds = Bounds{};
    lines.bounds.extend(glm::vec3(0.0f), 0.01f);
    const Check c =
        check(lines, rt::TileCover(lines), camera({0.3f, -3.5f, 1.2f}, Projection::Perspective), {}, 100, 60);
    EXPECT_GT(c.hitPixels, 500);
    EXPECT_EQ(c.missed, 0);
}

TEST(TileCover, data_at_or_behind_the_eye_plane) {
    const StyledLines lines = randomLines(7);
    const rt::TileCover cover(lines);
    // Perspective with the eye in the data: unknown (empty), every tile is traced.
    EXPECT_TRUE(cover.tiles(camera({0.0f, 0.0f, 0.0f}, Projection::Perspective), {}, 64, 48, rt::kTile).empty());
    // Orthographic from inside: the projection stays linear, the cover still holds.
    const Check c = check(lines, cover, camera({0.0f, 0.0f, 0.0f}, Projection::Orthographic), {}, 64, 48);
    EXPECT_EQ(c.missed, 0);
    // All data behind the eye: nothing to trace.
    Camera away = camera({0.0f, -3.0f, 0.0f}, Projection::Perspective);
    away.target = {0.0f, -6.0f, 0.0f};
    const std::vector<std::uint8_t> none = cover.tiles(away, {}, 64, 48, rt::kTile);
    ASSERT_FALSE(none.empty());
    EXPECT_EQ(std::count(none.begin(), none.end(), 1), 0);
    // No lines: no grid, unknown.
    EXPECT_TRUE(rt::TileCover(StyledLines{}).tiles(away, {}, 64, 48, rt::kTile).empty());
}

}  // namespace
}  // namespace tc
