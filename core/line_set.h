#pragma once
// Line sets as struct-of-arrays: what readers and generators produce and styling consumes.
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <string>
#include <vector>

namespace tc {

struct Bounds {
    glm::vec3 lo{std::numeric_limits<float>::infinity()};
    glm::vec3 hi{-std::numeric_limits<float>::infinity()};

    bool empty() const { return lo.x > hi.x; }
    void extend(const glm::vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const glm::vec3& p, float r) {
        lo = glm::min(lo, p - r);
        hi = glm::max(hi, p + r);
    }
    glm::vec3 center() const { return 0.5f * (lo + hi); }
    glm::vec3 extent() const { return hi - lo; }
    float radius() const { return 0.5f * glm::length(hi - lo); }  // of the bounding sphere
};

// One scalar per vertex (per point of a polyline). Vector attributes are split by readers into
// components named "name_x", "name_y", "name_z" plus "name_magnitude".
struct Attribute {
    std::string name;
    std::vector<float> values;
    // Range of the finite values; NaN when there is none.
    float min = std::numeric_limits<float>::quiet_NaN();
    float max = std::numeric_limits<float>::quiet_NaN();
    void updateRange();
};

// Polyline p has vertices [offsets[p], offsets[p + 1]). Every polyline has >= 2 vertices and no
// zero-length segment (see cleanLineSet); positions are finite.
struct LineSet {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> offsets{0};
    std::vector<Attribute> attributes;
    Bounds bounds;  // of the positions (radii are added by styling)
    // The vector attribute the lines follow (split into NAME_x/_y/_z and NAME_magnitude), when the
    // reader knows it: dataset.trace's vector. The derived attribute "speed" is its magnitude.
    std::string velocity;

    std::size_t polylineCount() const { return offsets.size() - 1; }
    std::size_t vertexCount() const { return positions.size(); }
    std::size_t segmentCount() const { return positions.size() - polylineCount(); }
    const Attribute* attribute(const std::string& name) const;
    void updateBounds();
};

// What cleaning removed and what the reader tolerated, so readers can report it ("skipped 3 NaN
// vertices ...").
struct CleanReport {
    std::size_t nonFiniteVertices = 0;  // NaN/Inf coordinates (the vertex is removed, the polyline split)
    std::size_t duplicateVertices = 0;  // zero-length segments removed
    std::size_t droppedPolylines = 0;   // fewer than 2 vertices left
    // Non-fatal problems of the file itself, each naming its position ("line 4: count: 7 tracks
    // declared, the data holds 2; read 2"); a file other than the one read is named too
    // ("tracks_fa.tsf: line 3: ..."). Set by the readers of io/, not by cleanLineSet.
    std::vector<std::string> warnings;
    bool any() const { return removed() || !warnings.empty(); }
    bool removed() const { return nonFiniteVertices || duplicateVertices || droppedPolylines; }
    // "skipped ..." for what cleaning removed, then the warnings, joined by "; ".
    std::string summary() const;
};

// Removes non-finite vertices (splitting the polyline there), consecutive duplicate vertices
// (zero-length segments) and polylines with fewer than two vertices; recomputes bounds and
// attribute ranges.
CleanReport cleanLineSet(LineSet& lines);

}  // namespace tc
