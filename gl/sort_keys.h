#pragma once
// The per-segment key pass of the visibility sort (Groß & Gumhold 2020, Sect. 4.1):
// shaders/segment_sort_keys.comp writes, for every segment S, the order-preserving uint32 key of
// its distance to the eye (core/sort_keys.h, bit-identical to the CPU's segmentSortKey) and the
// value S. RadixSort::sort on the two buffers then yields the front-to-back segment order; the
// draw fetches vertices segmentVertices[2S], [2S+1], so vertex data is never reordered.
#include <cstddef>
#include <glm/glm.hpp>

#include "core/frustum.h"
#include "gl/objects.h"

namespace tc::gl {

class SegmentSortKeys {
public:
    // Compiles the program. Needs a current context.
    static SegmentSortKeys create();

    // Writes `segments` keys into `keysOut` and segment ids 0..segments-1 into `segmentIdsOut`.
    // positionRadius: vec4 per vertex (xyz used); segmentVertices: 2 uint32 per segment.
    // Perspective (orthographic == false): key of the minimum distance from `eye` to the segment.
    // Orthographic: key of the minimum of dot(x - eye, forward) over the segment's end points
    // (`forward` unit length; may be negative). An output buffer that is empty or smaller than
    // segments * 4 bytes is replaced by a new one of exactly that size (never shrunk).
    // GL state: binds shader storage binding points 0..3, leaves no program bound; ends with
    // glMemoryBarrier(shader storage | buffer update) so the sort and readbacks see the keys.
    // With `frustum`, segments whose bounding sphere it excludes get key 0xFFFFFFFF (behind
    // every segment in view) and are counted for outsideCount().
    void compute(const Buffer& positionRadius, const Buffer& segmentVertices, std::size_t segments,
                 const glm::vec3& eye, bool orthographic, const glm::vec3& forward, Buffer& keysOut,
                 Buffer& segmentIdsOut, const ViewFrustum* frustum = nullptr);
    // Segments the last compute() with a frustum found outside it (0 without one). Waits for the
    // key pass (a read-back).
    std::size_t outsideCount() const;

private:
    SegmentSortKeys() = default;
    Program m_program;
    Buffer m_outside;  // one uint
    GLint m_segmentCount = -1, m_firstSegment = -1, m_eye = -1, m_forward = -1, m_orthographic = -1;
    GLint m_frustumTest = -1, m_frustumPlanes = -1;
};

}  // namespace tc::gl
