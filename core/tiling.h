#pragma once
// Large and anti-aliased images: the pure math behind rendering a frame as tiles and as
// jittered sub-pixel samples. A render target is a *window* of the full image: its pixels are
// full-image pixels shifted by an integer tile origin plus a sub-pixel sample offset. The GPU
// turns a window into an exact off-axis sub-frustum of the full camera (ray origins and
// directions through the shifted sample positions, billboards mapped from full-image NDC to the
// target's NDC), so every pixel of a tile casts bit-for-bit the ray the untiled image casts.
// core/tiled_technique.h renders the tiles and samples; gl/view_window.h sets the GLSL uniforms.
#include <cstddef>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "core/camera.h"

namespace tc {

struct Scene;

// Which part of the full image a render target covers, and where in each pixel its sample lies.
// The default (fullWidth == 0) is the whole image sampled at pixel centres.
struct ImageWindow {
    int fullWidth = 0, fullHeight = 0;  // the full image; 0 = the target is the full image
    int x = 0, y = 0;                   // the target's top-left pixel in the full image (row 0 = top)
    glm::vec2 jitter{0.0f};             // sample offset from the pixel centre in pixels (x right, y down)

    bool isFull() const { return fullWidth == 0 && jitter == glm::vec2(0.0f); }
};

// Target pixel (px, py) (row 0 = top) of a width x height target of `window` -> the continuous
// full-image pixel coordinate tc::pixelRay takes (its px, py: the sample lies at +0.5).
glm::vec2 fullImagePixel(const ImageWindow& window, float px, float py);
int fullWidthOf(const ImageWindow& window, int targetWidth);
int fullHeightOf(const ImageWindow& window, int targetHeight);

// Ray through the sample of target pixel (px, py): tc::pixelRay of the full image at the shifted
// position, so a full window gives exactly tc::pixelRay(camera, width, height, px, py).
Ray windowPixelRay(const Camera& camera, const ImageWindow& window, int targetWidth, int targetHeight, int px, int py);

// GL window coordinates (y up, gl_FragCoord) of the full image = target's + this offset.
glm::vec2 glWindowOffset(const ImageWindow& window, int targetWidth, int targetHeight);
// Full-image NDC -> target NDC: ndc * xy + zw. Exactly (1, 1, 0, 0) for a full window, so
// untiled single-sample renders rasterize exactly as before.
glm::vec4 ndcToTarget(const ImageWindow& window, int targetWidth, int targetHeight);

// One tile: a pixel rectangle of the full image, row 0 = top.
struct TileRect {
    int x = 0, y = 0, width = 0, height = 0;
    std::size_t pixelCount() const { return std::size_t(width) * std::size_t(height); }
};

// nx x ny tiles covering width x height, row-major from the top-left. Tile edges lie on even
// pixel coordinates counted from the left and from the BOTTOM (GL window coordinates), so the
// 2 x 2 texels of the culling pyramids (gl/hierarchical_culling.h) group the same pixels in every
// tile as in the untiled image and culling decides every fragment the same way. Tiles differ in
// size by at most 2 pixels per axis.
std::vector<TileRect> tileGrid(int width, int height, int nx, int ny);

// Auto-tiling cuts at most size / kMinTileEdge tiles per axis (tiles of about this edge or more):
// every tile repeats the per-frame passes that do not scale with pixels (billboards, culling).
constexpr int kMinTileEdge = 64;

// What one render target may not exceed on the GL at hand (0 = no limit): its edge
// (GL_MAX_TEXTURE_SIZE, GL_MAX_VIEWPORT_DIMS) and its pixels, through the largest per-pixel
// shader storage buffer (k-buffer entries, peeling keys) against GL_MAX_SHADER_STORAGE_BLOCK_SIZE
// (128 MiB on llvmpipe: 2M pixels of a k = 8 k-buffer).
struct TileLimits {
    int maxEdge = 0;
    std::size_t maxPixels = 0;
};

struct TilePlan {
    int nx = 1, ny = 1;
    bool automatic = false;         // chosen for render.memory_budget_mb, not image.tiles
    std::size_t bytesPerPixel = 0;  // GPU per-pixel buffers of the technique
    std::size_t largestTileBytes = 0;
    int largestTileWidth = 0, largestTileHeight = 0;
    std::vector<TileRect> tiles;
};

// The tiles of a width x height frame. requestedNx/Ny > 0: exactly that grid (image.tiles; an
// InputError naming it if a tile exceeds `limits`); 0: one tile if the whole image's per-pixel
// buffers fit `budgetBytes` and `limits`, else the grid with the fewest tiles (then the
// squarest) whose largest tile fits. Throws InputError naming render.memory_budget_mb when even
// the smallest tile of that grid does not fit (`what` describes the buffers, e.g. "kbuffer with
// k=8").
TilePlan planTiles(int width, int height, int requestedNx, int requestedNy, std::size_t bytesPerPixel,
                   std::size_t budgetBytes, const std::string& what, TileLimits limits = {});

// The tiles of `scene`'s frames: image.tiles, else by render.memory_budget_mb over `bytesPerPixel`
// (the technique's per-pixel buffers, core/technique_registry.h PixelBuffers; `what` names them in
// messages). One tile when the technique's pixels do not compose (`composes` false: it checks
// its own budget).
TilePlan planSceneTiles(const Scene& scene, std::size_t bytesPerPixel, const std::string& what, bool composes,
                        TileLimits limits = {});

// Sub-pixel sample offsets for image.samples = count, each in [-0.5, 0.5)^2 (x right, y down):
// the centred Hammersley set x_i = (i + 0.5) / N, y_i = radical inverse base 2 of i + 0.5 / N,
// minus 0.5, rounded to 1/256 pixel. The count is known before rendering, so a fixed-size set
// beats a progressive sequence: for N = 16 the fraction of samples on one side of any straight
// edge is within 0.13 of the covered area (mean 0.035), the first 16 R2 points (Roberts 2018)
// reach 0.22 (0.063) and Halton(2,3) 0.17 (0.045) (tests/unit/tiling_test.cpp measures it).
// N = 1 is the pixel centre, so samples = 1 renders exactly the plain image. The rounding keeps
// full-image sample coordinates (integer pixel + offset) exact in float up to 65536 pixels, so a
// tile's rays equal the untiled image's bit for bit with jitter too.
std::vector<glm::vec2> sampleOffsets(int count);
// Index of the offset nearest the pixel centre (the first of equals): the sample whose depth,
// normal and id an anti-aliased frame keeps.
std::size_t nearestToCentre(const std::vector<glm::vec2>& offsets);

}  // namespace tc
