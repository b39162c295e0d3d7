#pragma once
// Which 8x8 tiles of a frame the tubes may show in: the ray tracer traces only those (the others are
// background, rt/primary_rays.h forEachTile). A ray that misses every tube still costs Embree a
// descent into the BVH wherever it crosses the data's bounding box, and on a view of a dense ball
// of lines most such rays pass the box's corners; the scene box alone (pixelBlockMisses) keeps
// them. The cover is a uniform grid over the tubes (every segment's box grown by its radius marks
// the cells it overlaps); per frame each occupied cell's eight corners are projected and the
// tiles under their bounding rectangle, grown by a margin, are marked. A projected box lies in the
// hull of its projected corners (the cell lies in front of the eye), so every point of every tube
// projects into a marked tile: skipping the others changes no pixel (tests/unit/tile_cover_test.cpp).
// Embree offers no access to its own BVH nodes for such a test, hence the grid.
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/camera.h"
#include "core/styled_lines.h"
#include "core/tiling.h"

namespace tc::rt {

class TileCover {
public:
    TileCover() = default;
    // The grid over `lines` with `cellsAlongLongestAxis` cells along the longest side of their
    // bounds (the others in proportion, at least one).
    explicit TileCover(const StyledLines& lines, int cellsAlongLongestAxis = 32);

    // Per tile of a width x height target of `window`, tile t = ty * tilesX + tx as forEachTile
    // numbers them: 1 where a tube may be seen, 0 where none can. Empty when the cover cannot
    // tell (a cell reaches the plane of a perspective eye, or no grid): then every tile counts.
    std::vector<std::uint8_t> tiles(const Camera& camera, const ImageWindow& window, int width, int height,
                                    int tileSize) const;

    std::size_t occupiedCells() const { return m_cells.size(); }

private:
    glm::vec3 m_origin{0.0f};
    float m_cell = 0;                   // cube cells of this side
    std::vector<glm::u16vec3> m_cells;  // occupied cells' integer coordinates
};

}  // namespace tc::rt
