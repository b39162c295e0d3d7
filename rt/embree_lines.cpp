#include "rt/embree_lines.h"

#include <atomic>
#include <chrono>
#include <cstring>
#include <string>

#include "core/error.h"

namespace tc::rt {
namespace {

bool monitorMemory(void* user, ssize_t bytes, bool /*post*/) {
    auto* c = static_cast<MemoryCounter*>(user);
    std::int64_t now = c->current.fetch_add(bytes) + bytes;
    std::int64_t peak = c->peak.load();
    while (now > peak && !c->peak.compare_exchange_weak(peak, now)) {
    }
    return true;
}

void throwOnError(RTCDevice device, const char* what) {
    RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
        throw Error(ExitCode::Internal,
                    std::string("Embree: ") + what + " failed with error " + std::to_string(int(e)));
}

}  // namespace

EmbreeLines::EmbreeLines(const StyledLines& lines, bool joinNeighbours, bool contextFilter) : m_joined(joinNeighbours) {
    const std::size_t segments = lines.segmentCount();
    for (std::size_t s = 0; s < segments; ++s)
        if (lines.segmentVertices[2 * s + 1] != lines.segmentVertices[2 * s] + 1)
            throw InputError("raytraced: segment " + std::to_string(s) +
                             " does not join consecutive vertices (Embree curves need v, v + 1)");

    m_memory = std::make_unique<MemoryCounter>();
    MemoryCounter& counter = *m_memory;
    auto t0 = std::chrono::steady_clock::now();
    m_device = rtcNewDevice(nullptr);
    if (!m_device) throw Error(ExitCode::Internal, "Embree: rtcNewDevice failed (unsupported CPU?)");
    rtcSetDeviceMemoryMonitorFunction(m_device, monitorMemory, &counter);

    m_scene = rtcNewScene(m_device);
    rtcSetSceneFlags(m_scene, contextFilter ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_MEDIUM);
    if (segments > 0) {
        RTCGeometry geom = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
        // Embree-owned copies: the technique must not depend on the caller keeping `lines` alive,
        // and Embree's buffers get the padding its vector loads need.
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                              4 * sizeof(float), lines.vertexCount()));
        std::memcpy(v, lines.positionRadius.data(), lines.vertexCount() * sizeof(glm::vec4));
        auto* idx = static_cast<std::uint32_t*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(std::uint32_t), segments));
        for (std::size_t s = 0; s < segments; ++s) idx[s] = lines.segmentVertices[2 * s];
        // Always set: without a flags buffer Embree does not treat segments as closed rounded cones.
        auto* flags = static_cast<std::uint8_t*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, 1, segments));
        std::memset(flags, 0, segments);
        if (joinNeighbours) {
            const bool haveFlags = !lines.flags.empty();
            for (std::size_t s = 0; s < segments; ++s) {
                const std::uint32_t v0 = idx[s], v1 = v0 + 1;
                std::uint8_t f = 0;
                // The same "polyline continues" test as segmentClipPlanes (core/cap_clipping.cpp).
                if (!(haveFlags && (lines.flags[v0] & FirstOfPolyline)) && v0 > 0 &&
                    lines.polylineId[v0 - 1] == lines.polylineId[v0])
                    f |= RTC_CURVE_FLAG_NEIGHBOR_LEFT;
                if (!(haveFlags && (lines.flags[v1] & LastOfPolyline)) && v1 + 1 < lines.vertexCount() &&
                    lines.polylineId[v1 + 1] == lines.polylineId[v1])
                    f |= RTC_CURVE_FLAG_NEIGHBOR_RIGHT;
                flags[s] = f;
            }
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometry(m_scene, geom);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(m_scene);
    throwOnError(m_device, "building the line BVH");
    m_buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    m_bytes = std::size_t(std::max<std::int64_t>(counter.current.load(), 0));
    m_peakBytes = std::size_t(std::max<std::int64_t>(counter.peak.load(), 0));
}

EmbreeLines::~EmbreeLines() {
    if (m_scene) rtcReleaseScene(m_scene);
    if (m_device) rtcReleaseDevice(m_device);
}

}  // namespace tc::rt
