#pragma once
// A line set resolved by styling into what renderers draw: per-vertex radius and linear,
// straight (non-premultiplied) RGBA, and the segment index buffer.
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/line_set.h"

namespace tc {

// Per-vertex flags (bits of StyledLines::flags).
enum VertexFlag : std::uint32_t {
    FirstOfPolyline = 1u,  // keeps a full cap at the start (cap clipping)
    LastOfPolyline = 2u,   // keeps a full cap at the end
};

struct StyledLines {
    std::vector<glm::vec4> positionRadius;  // xyz world position, w radius (> 0)
    std::vector<glm::vec4> color;           // linear RGB, straight alpha in [0,1]
    std::vector<std::uint32_t> polylineId;  // per vertex
    std::vector<std::uint32_t> flags;       // per vertex, VertexFlag bits
    // Segment S joins vertices segmentVertices[2S] and segmentVertices[2S + 1]. A sort permutes
    // segment ids; vertex data never moves (Groß & Gumhold 2020, Sect. 4.1).
    std::vector<std::uint32_t> segmentVertices;
    // Per polyline, or empty: the rotation-minimising frame's tangent the source polyline carries
    // into this one's first segment when this polyline is a run cut from it (core/
    // kd_decomposition.h, incomingTangents), 0 for one that starts its source polyline. Empty:
    // every polyline starts its own frame. The AO line cache's azimuths follow it.
    std::vector<glm::vec3> incomingTangent;
    Bounds bounds;  // of the tubes (positions grown by radii)
    float maxRadius = 0;

    std::size_t segmentCount() const { return segmentVertices.size() / 2; }
    std::size_t vertexCount() const { return positionRadius.size(); }
};

}  // namespace tc
