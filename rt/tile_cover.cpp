#include "rt/tile_cover.h"

#include <algorithm>
#include <cmath>

namespace tc::rt {

TileCover::TileCover(const StyledLines& lines, int cellsAlongLongestAxis) {
    const std::size_t segments = lines.segmentCount();
    if (segments == 0 || cellsAlongLongestAxis < 1) return;
    // The grid's bounds from the segments themselves, not lines.bounds: the cover must hold every
    // tube even where a caller's bounds are of other data (a union over ranks or frames).
    Bounds bounds;
    for (std::size_t s = 0; s < segments; ++s)
        for (int e = 0; e < 2; ++e) {
            const glm::vec4& v = lines.positionRadius[lines.segmentVertices[2 * s + std::size_t(e)]];
            bounds.extend(glm::vec3(v), v.w);
        }
    const glm::vec3 extent = bounds.hi - bounds.lo;
    const float longest = std::max({extent.x, extent.y, extent.z});
    if (!(longest > 0.0f) || !std::isfinite(longest)) return;
    const float size = longest / float(cellsAlongLongestAxis);
    glm::ivec3 res;
    for (int a = 0; a < 3; ++a) res[a] = std::clamp(int(std::ceil(extent[a] / size)), 1, cellsAlongLongestAxis);
    m_origin = bounds.lo;
    m_cell = size;
    // A segment's box, grown by its radius and by a little of a cell for the rounding of hit
    // points on its surface, marks every cell it overlaps.
    const float pad = 1e-3f * size;
    std::vector<std::uint8_t> occupied(std::size_t(res.x) * std::size_t(res.y) * std::size_t(res.z), 0);
    auto cellOf = [&](const glm::vec3& p) {
        return glm::clamp(glm::ivec3(glm::floor((p - m_origin) / size)), glm::ivec3(0), res - 1);
    };
    for (std::size_t s = 0; s < segments; ++s) {
        const glm::vec4& a = lines.positionRadius[lines.segmentVertices[2 * s]];
        const glm::vec4& b = lines.positionRadius[lines.segmentVertices[2 * s + 1]];
        const float r = std::max(a.w, b.w) + pad;
        const glm::ivec3 lo = cellOf(glm::min(glm::vec3(a), glm::vec3(b)) - r);
        const glm::ivec3 hi = cellOf(glm::max(glm::vec3(a), glm::vec3(b)) + r);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x)
                    occupied[(std::size_t(z) * std::size_t(res.y) + std::size_t(y)) * std::size_t(res.x) +
                             std::size_t(x)] = 1;
    }
    for (int z = 0; z < res.z; ++z)
        for (int y = 0; y < res.y; ++y)
            for (int x = 0; x < res.x; ++x)
                if (occupied[(std::size_t(z) * std::size_t(res.y) + std::size_t(y)) * std::size_t(res.x) +
                             std::size_t(x)])
                    m_cells.emplace_back(x, y, z);
}

std::vector<std::uint8_t> TileCover::tiles(const Camera& camera, const ImageWindow& window, int width, int height,
                                           int tileSize) const {
    if (m_cells.empty() || width <= 0 || height <= 0) return {};
    const int tilesX = (width + tileSize - 1) / tileSize, tilesY = (height + tileSize - 1) / tileSize;
    std::vector<std::uint8_t> mask(std::size_t(tilesX) * std::size_t(tilesY), 0);
    const bool ortho = camera.projection == Projection::Orthographic;
    const glm::vec3 f = camera.forward(), r = camera.right(), u = camera.trueUp();
    const float fullW = float(fullWidthOf(window, width)), fullH = float(fullHeightOf(window, height));
    const float halfExtent = ortho ? 0.5f * camera.orthoHeight : std::tan(glm::radians(camera.fovYDeg) * 0.5f);
    const float aspect = fullW / fullH;
    // Continuous full-image position X of a point (tc::PixelRays: the sample of target pixel px
    // lies at X = window.x + px + jitter.x + 0.5; the same in y with rows downwards): the target
    // pixel is X - 0.5 - window.x - jitter.x. Two pixels of margin cover the rounding of rays and
    // of this projection many times over.
    const float margin = 2.0f;
    const float offX = 0.5f + float(window.x) + window.jitter.x, offY = 0.5f + float(window.y) + window.jitter.y;
    // Coordinates along r, u, f are linear over the grid: the corner (i, j, k) of the grid is
    // base + i * stepX + j * stepY + k * stepZ.
    const glm::vec3 base(glm::dot(m_origin - camera.eye, r), glm::dot(m_origin - camera.eye, u),
                         glm::dot(m_origin - camera.eye, f));
    const glm::vec3 stepX = m_cell * glm::vec3(r.x, u.x, f.x);
    const glm::vec3 stepY = m_cell * glm::vec3(r.y, u.y, f.y);
    const glm::vec3 stepZ = m_cell * glm::vec3(r.z, u.z, f.z);
    // Depth below which a perspective projection is not trusted: a cell reaching it makes the
    // cover unknown (the eye is in or next to the data).
    const float zMin = 1e-3f * std::sqrt(3.0f) * m_cell;
    for (const glm::u16vec3& c : m_cells) {
        const glm::vec3 p0 = base + float(c.x) * stepX + float(c.y) * stepY + float(c.z) * stepZ;
        float x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY, zLo = INFINITY, zHi = -INFINITY;
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 p = p0 + ((k & 1) ? stepX : glm::vec3(0.0f)) + ((k & 2) ? stepY : glm::vec3(0.0f)) +
                                ((k & 4) ? stepZ : glm::vec3(0.0f));
            zLo = std::min(zLo, p.z);
            zHi = std::max(zHi, p.z);
            const float w = ortho ? 1.0f : p.z;
            // NDC (sx, sy) as PixelRays: the point is eye + z (f + sx h a r + sy h u).
            const float sx = p.x / (w * halfExtent * aspect), sy = p.y / (w * halfExtent);
            x0 = std::min(x0, sx), x1 = std::max(x1, sx), y0 = std::min(y0, sy), y1 = std::max(y1, sy);
        }
        if (zHi <= 0.0f) continue;  // behind the eye's plane: no ray reaches it (t > 0, dir . f > 0)
        if (!ortho && zLo <= zMin) return {};
        // NDC -> target pixels: X = (sx + 1) W / 2, Y = (1 - sy) H / 2.
        const float px0 = (x0 + 1.0f) * 0.5f * fullW - offX - margin, px1 = (x1 + 1.0f) * 0.5f * fullW - offX + margin;
        const float py0 = (1.0f - y1) * 0.5f * fullH - offY - margin, py1 = (1.0f - y0) * 0.5f * fullH - offY + margin;
        if (!(px1 >= 0.0f && py1 >= 0.0f && px0 < float(width) && py0 < float(height))) continue;
        const int tx0 = int(std::max(px0, 0.0f)) / tileSize;
        const int tx1 = std::min(tilesX - 1, int(std::min(px1, float(width))) / tileSize);
        const int ty0 = int(std::max(py0, 0.0f)) / tileSize;
        const int ty1 = std::min(tilesY - 1, int(std::min(py1, float(height))) / tileSize);
        for (int ty = ty0; ty <= ty1; ++ty)
            std::fill(mask.begin() + std::ptrdiff_t(ty * tilesX + tx0),
                      mask.begin() + std::ptrdiff_t(ty * tilesX + tx1) + 1, std::uint8_t(1));
    }
    return mask;
}

}  // namespace tc::rt
