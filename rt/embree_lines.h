#pragma once
// The Embree 3 scene of a styled line set: one RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE geometry whose
// primitive S is segment S of StyledLines (vertices v, v + 1; per-vertex radius in the vertex
// buffer's w). Built once per dataset. With `joinNeighbours`, each segment carries
// RTC_CURVE_FLAG_NEIGHBOR_LEFT / RIGHT when its polyline continues there, and Embree renders a
// polyline as ONE tube: the union of its rounded cones without internal surfaces (Embree's
// round_linear_curve = cone_sphere(p0..p1) minus the neighbours' cones), so a ray enters and
// leaves a polyline's tube once per crossing. Without, every segment is a closed rounded cone.
#include <embree3/rtcore.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "core/styled_lines.h"

namespace tc::rt {

struct MemoryCounter {
    std::atomic<std::int64_t> current{0};
    std::atomic<std::int64_t> peak{0};
};

class EmbreeLines {
public:
    // Copies positions/radii and segment starts into Embree-owned buffers and commits the BVH.
    // `contextFilter` enables the per-query filter callback (RTCIntersectContext::filter) the
    // transparent path collects hits with. Throws tc::Error(Internal) when Embree reports an
    // error, InputError when the segments are not (v, v + 1) pairs (the layout styleLines builds).
    EmbreeLines(const StyledLines& lines, bool joinNeighbours, bool contextFilter);
    ~EmbreeLines();
    EmbreeLines(const EmbreeLines&) = delete;
    EmbreeLines& operator=(const EmbreeLines&) = delete;

    RTCScene scene() const { return m_scene; }
    double buildMs() const { return m_buildMs; }
    // Bytes Embree held after the commit (BVH, its buffers and our copies of the vertex, index and
    // flag data), and the peak during the build, from the device's memory monitor.
    std::size_t bytes() const { return m_bytes; }
    std::size_t peakBytes() const { return m_peakBytes; }
    bool joinedNeighbours() const { return m_joined; }

private:
    // Declared first: destroyed after the device, whose memory monitor writes into it.
    std::unique_ptr<MemoryCounter> m_memory;
    RTCDevice m_device = nullptr;
    RTCScene m_scene = nullptr;
    double m_buildMs = 0;
    std::size_t m_bytes = 0, m_peakBytes = 0;
    bool m_joined = false;
};

}  // namespace tc::rt
