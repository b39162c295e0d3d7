#include "core/tiling.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/scene.h"

namespace tc {

glm::vec2 fullImagePixel(const ImageWindow& window, float px, float py) {
    return {float(window.x) + px + window.jitter.x, float(window.y) + py + window.jitter.y};
}

int fullWidthOf(const ImageWindow& window, int targetWidth) {
    return window.fullWidth > 0 ? window.fullWidth : targetWidth;
}

int fullHeightOf(const ImageWindow& window, int targetHeight) {
    return window.fullHeight > 0 ? window.fullHeight : targetHeight;
}

Ray windowPixelRay(const Camera& camera, const ImageWindow& window, int targetWidth, int targetHeight, int px, int py) {
    const glm::vec2 p = fullImagePixel(window, float(px), float(py));
    return pixelRay(camera, fullWidthOf(window, targetWidth), fullHeightOf(window, targetHeight), p.x, p.y);
}

glm::vec2 glWindowOffset(const ImageWindow& window, int targetWidth, int targetHeight) {
    // A target fragment at (i + 0.5, j + 0.5) samples image pixel (x + i, y + targetHeight - 1 - j)
    // at its centre plus the jitter; GL's y runs up, the image's rows down.
    (void)targetWidth;
    const int fullHeight = fullHeightOf(window, targetHeight);
    return {float(window.x) + window.jitter.x, float(fullHeight - window.y - targetHeight) - window.jitter.y};
}

glm::vec4 ndcToTarget(const ImageWindow& window, int targetWidth, int targetHeight) {
    // Full window coordinate X = (ndc + 1) / 2 * W; target X' = X - offset; ndc' = 2 X' / w - 1.
    const double fw = fullWidthOf(window, targetWidth), fh = fullHeightOf(window, targetHeight);
    const glm::vec2 off = glWindowOffset(window, targetWidth, targetHeight);
    const double sx = fw / targetWidth, sy = fh / targetHeight;
    const double bx = (fw - 2.0 * double(off.x)) / targetWidth - 1.0;
    const double by = (fh - 2.0 * double(off.y)) / targetHeight - 1.0;
    return {float(sx), float(sy), float(bx), float(by)};
}

namespace {

// Edges of n parts of `size` on even coordinates (the last one is `size`).
std::vector<int> evenEdges(int size, int n) {
    std::vector<int> edges(std::size_t(n) + 1);
    for (int i = 0; i < n; ++i) edges[std::size_t(i)] = 2 * int((std::int64_t(i) * size) / (2 * std::int64_t(n)));
    edges[std::size_t(n)] = size;
    return edges;
}

int largestPart(int size, int n) {
    const std::vector<int> e = evenEdges(size, n);
    int largest = 0;
    for (int i = 0; i < n; ++i) largest = std::max(largest, e[std::size_t(i) + 1] - e[std::size_t(i)]);
    return largest;
}

std::string megabytes(std::size_t bytes) {
    return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MB";
}

}  // namespace

std::vector<TileRect> tileGrid(int width, int height, int nx, int ny) {
    TC_CHECK(width > 0 && height > 0);
    TC_CHECK(nx >= 1 && ny >= 1 && 2 * nx <= std::max(width, 2) && 2 * ny <= std::max(height, 2));
    const std::vector<int> xs = evenEdges(width, nx);
    const std::vector<int> ysUp = evenEdges(height, ny);  // from the bottom row, GL style
    std::vector<TileRect> tiles;
    for (int j = ny - 1; j >= 0; --j)  // the top tile row first
        for (int i = 0; i < nx; ++i) {
            TileRect t;
            t.x = xs[std::size_t(i)];
            t.width = xs[std::size_t(i) + 1] - t.x;
            t.height = ysUp[std::size_t(j) + 1] - ysUp[std::size_t(j)];
            t.y = height - ysUp[std::size_t(j) + 1];
            tiles.push_back(t);
        }
    return tiles;
}

TilePlan planTiles(int width, int height, int requestedNx, int requestedNy, std::size_t bytesPerPixel,
                   std::size_t budgetBytes, const std::string& what, TileLimits limits) {
    TilePlan plan;
    plan.bytesPerPixel = bytesPerPixel;
    auto bytesOf = [&](int w, int h) { return std::size_t(w) * std::size_t(h) * bytesPerPixel; };
    auto withinLimits = [&](int w, int h) {
        return (limits.maxEdge == 0 || std::max(w, h) <= limits.maxEdge) &&
               (limits.maxPixels == 0 || std::size_t(w) * std::size_t(h) <= limits.maxPixels);
    };
    auto fits = [&](int w, int h) { return bytesOf(w, h) <= budgetBytes && withinLimits(w, h); };
    if (requestedNx > 0 && requestedNy > 0) {
        plan.nx = requestedNx;
        plan.ny = requestedNy;
        const int tw = largestPart(width, requestedNx), th = largestPart(height, requestedNy);
        if (!withinLimits(tw, th))
            throw InputError("image.tiles: tiles of " + std::to_string(tw) + "x" + std::to_string(th) +
                             " exceed what this GL renders at once (edge " + std::to_string(limits.maxEdge) + ", " +
                             std::to_string(limits.maxPixels) + " pixels for the " + what +
                             "); use more tiles or \"auto\"");
    } else if (!fits(width, height)) {
        plan.automatic = true;
        // Largest part per count, per axis; then the fewest tiles, ties to the squarest tiles.
        const int maxNx = std::max(1, width / kMinTileEdge), maxNy = std::max(1, height / kMinTileEdge);
        std::vector<int> partW(std::size_t(maxNx) + 1), partH(std::size_t(maxNy) + 1);
        for (int n = 1; n <= maxNx; ++n) partW[std::size_t(n)] = largestPart(width, n);
        for (int n = 1; n <= maxNy; ++n) partH[std::size_t(n)] = largestPart(height, n);
        const int minW = partW[std::size_t(maxNx)], minH = partH[std::size_t(maxNy)];
        const std::size_t minBytes = bytesOf(minW, minH);
        if (!withinLimits(minW, minH))
            throw InputError("image.tiles: even the smallest tile (" + std::to_string(minW) + "x" +
                             std::to_string(minH) + ") exceeds what this GL renders at once");
        if (minBytes > budgetBytes)
            throw InputError("render.memory_budget_mb: " + what + " needs " + megabytes(bytesOf(width, height)) +
                             " of per-pixel buffers at " + std::to_string(width) + "x" + std::to_string(height) +
                             " and " + megabytes(minBytes) + " for even the smallest tile (" + std::to_string(minW) +
                             "x" + std::to_string(minH) + "), over the budget of " + std::to_string(budgetBytes >> 20) +
                             " MB (raise the budget)");
        long best = std::numeric_limits<long>::max();
        double bestAspect = 0;
        for (int ny = 1; ny <= maxNy; ++ny)
            for (int nx = 1; nx <= maxNx; ++nx) {
                const int tw = partW[std::size_t(nx)], th = partH[std::size_t(ny)];
                if (!fits(tw, th)) continue;
                const long count = long(nx) * ny;
                const double aspect = std::abs(std::log(double(tw) / th));
                if (count < best || (count == best && aspect < bestAspect)) {
                    best = count;
                    bestAspect = aspect;
                    plan.nx = nx;
                    plan.ny = ny;
                }
            }
    }
    plan.tiles = tileGrid(width, height, plan.nx, plan.ny);
    for (const TileRect& t : plan.tiles) {
        plan.largestTileWidth = std::max(plan.largestTileWidth, t.width);
        plan.largestTileHeight = std::max(plan.largestTileHeight, t.height);
        plan.largestTileBytes = std::max(plan.largestTileBytes, bytesOf(t.width, t.height));
    }
    return plan;
}

TilePlan planSceneTiles(const Scene& scene, std::size_t bytesPerPixel, const std::string& what, bool composes,
                        TileLimits limits) {
    const ImageSpec& im = scene.image;
    if (!composes) return planTiles(im.width, im.height, 1, 1, 0, 0, "");
    return planTiles(im.width, im.height, im.tilesX, im.tilesY, bytesPerPixel,
                     std::size_t(scene.render.memoryBudgetMb) * 1024 * 1024, what, limits);
}

std::vector<glm::vec2> sampleOffsets(int count) {
    TC_CHECK(count >= 1);
    auto radicalInverse2 = [](unsigned i) {
        double r = 0, f = 0.5;
        for (; i; i >>= 1, f *= 0.5) r += f * double(i & 1u);
        return r;
    };
    auto quantise = [](double v) { return float(std::round(v * 256.0) / 256.0); };
    std::vector<glm::vec2> offsets;
    for (int i = 0; i < count; ++i) {
        const double x = (i + 0.5) / count, y = radicalInverse2(unsigned(i)) + 0.5 / count;
        offsets.emplace_back(quantise(x - 0.5), quantise(y - std::floor(y) - 0.5));
    }
    return offsets;
}

std::size_t nearestToCentre(const std::vector<glm::vec2>& offsets) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < offsets.size(); ++i)
        if (glm::dot(offsets[i], offsets[i]) < glm::dot(offsets[best], offsets[best])) best = i;
    return best;
}

}  // namespace tc
