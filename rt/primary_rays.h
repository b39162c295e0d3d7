#pragma once
// Primary rays of the ray tracers (tubes: rt/raytraced_renderer.h, particles:
// rt/raytraced_particles.h): the image in 8x8 pixel tiles over oneTBB, the camera rays of a tile
// (core/camera.h PixelRays, bit-identical to tc::pixelRay), and the opaque first hit of a tile by
// one of Embree's traversal interfaces.
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/tiling.h"

namespace tc::rt {

constexpr int kTile = 8;

// How opaque primary rays traverse the BVH. All give identical hits; RaytracedRenderer's default
// is the one measured fastest on the 1M tornado (16-ray packets, docs/performance.md, "Design
// notes"; `scripts/bench/raytraced.sh 3 7 stages` compares them all), the others stay
// selectable for tests/bench/raytraced_bench.cpp.
enum class Traversal {
    Single,    // rtcIntersect1 per pixel
    Packet8,   // rtcIntersect8 per 8-pixel tile row, RTC_INTERSECT_CONTEXT_FLAG_COHERENT
    Packet16,  // rtcIntersect16 per two tile rows (8x2 pixels), RTC_INTERSECT_CONTEXT_FLAG_COHERENT
    Stream,    // rtcIntersect1M over the tile's 64 rays, RTC_INTERSECT_CONTEXT_FLAG_COHERENT
};
const char* traversalName(Traversal t);

// The primary rays of one tile, row-major; pixels outside the image are not in it.
struct Tile {
    int x0 = 0, y0 = 0, w = 0, h = 0;
    // No ray of the tile can meet the scene's bounds (forEachTile with bounds): `rays` are not
    // set, every pixel is background.
    bool outside = false;
    Ray rays[kTile * kTile];
    int count() const { return w * h; }
    int px(int k) const { return x0 + k % w; }
    int py(int k) const { return y0 + k / w; }
};

struct FirstHit {
    bool hit = false;
    std::uint32_t prim = 0;
    float t = 0;
    glm::vec3 ng{0.0f};  // Embree's geometric normal, unnormalised
};

// A ray from `tnear` to infinity, no hit yet, for rtcIntersect1.
inline RTCRayHit makeRayHit(const Ray& ray, float tnear) {
    RTCRayHit rh;
    rh.ray.org_x = ray.origin.x;
    rh.ray.org_y = ray.origin.y;
    rh.ray.org_z = ray.origin.z;
    rh.ray.dir_x = ray.dir.x;
    rh.ray.dir_y = ray.dir.y;
    rh.ray.dir_z = ray.dir.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

// hits[k] = the first hit of tile.rays[k] in `scene` (geometry 0).
void traceFirstHits(RTCScene scene, Traversal traversal, const Tile& tile, FirstHit* hits);

// Axis-aligned bounds of everything the scene's rays can hit (rtcGetSceneBounds).
struct SceneBounds {
    glm::vec3 lo{0.0f}, hi{0.0f};
};
SceneBounds sceneBounds(RTCScene scene);

// Whether no sample ray of the target pixels [x0, x0 + w) x [y0, y0 + h) can meet the box. Those
// rays lie inside the pyramid (perspective; the prism, orthographic) spanned by the rays through
// the block's outer corners, here taken one pixel further out (sample jitter is at most half a
// pixel, and it covers rounding); the box misses if it lies entirely outside one of its four
// sides. Conservative: false whenever in doubt.
bool pixelBlockMisses(const PixelRays& rays, const ImageWindow& window, int x0, int y0, int w, int h,
                      const SceneBounds& box);

// Calls fn(tile) for every tile of a width x height image, in parallel; fn must only write the
// tile's own pixels (then images do not depend on the thread count).
// `window`: which part of the full image (and which sub-pixel sample) the width x height target
// is (core/tiling.h: tiles, image.samples); rays are those of the full image's pixels.
// With `bounds`, a tile none of whose rays can meet them is passed with `outside` set and no rays
// (in a fitted view of the 1M tornado two thirds of the tiles; their rays cost a third of an
// opaque frame, docs/performance.md, "Design notes").
// With a non-empty `cover` (rt/tile_cover.h TileCover::tiles, kTile), a tile it marks 0 is passed
// as `outside` too.
template <class TileFn>
void forEachTile(const Camera& camera, const ImageWindow& window, int width, int height, TileFn&& fn,
                 const SceneBounds* bounds = nullptr, const std::vector<std::uint8_t>* cover = nullptr) {
    const bool covered = cover && !cover->empty();
    const PixelRays pixelRays(camera, fullWidthOf(window, width), fullHeightOf(window, height));
    const int tilesX = (width + kTile - 1) / kTile, tilesY = (height + kTile - 1) / kTile;
    tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 1), [&](const tbb::blocked_range<int>& range) {
        Tile tile;
        for (int t = range.begin(); t != range.end(); ++t) {
            tile.x0 = (t % tilesX) * kTile;
            tile.y0 = (t / tilesX) * kTile;
            tile.w = std::min(kTile, width - tile.x0);
            tile.h = std::min(kTile, height - tile.y0);
            tile.outside = (covered && !(*cover)[std::size_t(t)]) ||
                           (bounds && pixelBlockMisses(pixelRays, window, tile.x0, tile.y0, tile.w, tile.h, *bounds));
            if (tile.outside) {
                fn(tile);
                continue;
            }
            // Rows and columns, not px(k) / py(k): two integer divisions per pixel were a
            // measurable part of a frame whose rays mostly miss (`tubecast_raytraced_bench SCENE`).
            for (int row = 0, k = 0; row < tile.h; ++row)
                for (int col = 0; col < tile.w; ++col, ++k) {
                    const glm::vec2 p = fullImagePixel(window, float(tile.x0 + col), float(tile.y0 + row));
                    tile.rays[k] = pixelRays(p.x, p.y);
                }
            fn(tile);
        }
    });
}

// The first-surface AOVs of one pixel (core/frame_images.h); an AOV buffer left empty
// (FrameImages::resize with KeptAovs) is not written.
inline void storeAovs(FrameImages& out, std::size_t i, float depth, const glm::vec3& normal, std::uint32_t id) {
    if (!out.depth.empty()) out.depth[i] = depth;
    if (!out.normal.empty()) {
        out.normal[3 * i + 0] = normal.x;
        out.normal[3 * i + 1] = normal.y;
        out.normal[3 * i + 2] = normal.z;
    }
    if (!out.id.empty()) out.id[i] = id;
}

// The visible surface of one pixel into the frame's buffers: colour and storeAovs.
inline void storePixel(FrameImages& out, std::size_t i, const glm::vec4& rgba, float depth, const glm::vec3& normal,
                       std::uint32_t id) {
    out.rgba[4 * i + 0] = rgba.x;
    out.rgba[4 * i + 1] = rgba.y;
    out.rgba[4 * i + 2] = rgba.z;
    out.rgba[4 * i + 3] = rgba.w;
    storeAovs(out, i, depth, normal, id);
}

// Every pixel of `tile` as background: FrameImages::allocate's clear values, AO 1 (when `out`
// has an AO buffer). For the tiles forEachTile passes `outside`.
inline void storeBackground(FrameImages& out, const Tile& tile, int width) {
    for (int row = 0; row < tile.h; ++row)
        for (int col = 0; col < tile.w; ++col) {
            const std::size_t pixel = std::size_t(tile.y0 + row) * std::size_t(width) + std::size_t(tile.x0 + col);
            storePixel(out, pixel, glm::vec4(0.0f), std::numeric_limits<float>::infinity(), glm::vec3(0.0f),
                       kBackgroundId);
            if (!out.ao.empty()) out.ao[pixel] = 1.0f;
        }
}

}  // namespace tc::rt
