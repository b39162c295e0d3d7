#pragma once
// A region of space for data-parallel rendering: one cell of a k-d decomposition
// (core/kd_decomposition.h). Regions tile space without overlap: each is half-open, [lo, hi) per
// axis, and the outermost faces are infinite. A tube or sphere contributes to the region that holds
// the point where the ray ENTERS it (the visible hit of an opaque frame, each front-facing entry
// of a transparent one), so every contribution to a pixel belongs to exactly one region and the
// regions' images composited in view order are the whole frame's.
#include <glm/glm.hpp>
#include <limits>

namespace tc {

struct RegionBox {
    glm::vec3 lo{-std::numeric_limits<float>::infinity()};
    glm::vec3 hi{std::numeric_limits<float>::infinity()};

    bool contains(const glm::vec3& p) const {
        return p.x >= lo.x && p.x < hi.x && p.y >= lo.y && p.y < hi.y && p.z >= lo.z && p.z < hi.z;
    }
    bool unbounded() const { return *this == RegionBox{}; }
    friend bool operator==(const RegionBox&, const RegionBox&) = default;
};

}  // namespace tc
