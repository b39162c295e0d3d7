#include "gl/ao_line_cache.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <vector>

#include "core/error.h"
#include "core/tangent_frame.h"
#include "gl/bindings.h"
#include "gl/gl_util.h"
#include "gl/shader_library.h"

namespace tc::gl {
AoLineCache AoLineCache::build(const LineGeometry& geometry, const StyledLines& lines, float spacing,
                               const std::function<void(GLuint)>& setAoUniforms) {
    TC_CHECK(spacing > 0.0f);
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();  // process CPU time, llvmpipe's threads included
    AoLineCache cache;
    cache.m_spacing = spacing;
    const std::size_t segments = lines.segmentCount();
    // Layout of shaders/ao_line_cache.glsl, two words per segment: the first sample's index, with
    // kJoinedBit when the segment starts at the previous one's end vertex (it shares its first
    // sample with that one's last), and the azimuth origin (float bits): the angle from the
    // segment's coneTangentFrame tangent to the tangent parallel-transported along the polyline
    // (rotation-minimising), so azimuth k means the same side of the tube on both sides of a
    // joint and the shared sample needs no second frame in the lookup.
    std::vector<std::uint32_t> words(2 * (segments + 1), 0u);
    std::size_t total = 0;
    glm::vec3 transported(0.0f);
    for (std::size_t s = 0; s < segments; ++s) {
        const bool joined = s > 0 && lines.segmentVertices[2 * s] == lines.segmentVertices[2 * s - 1];
        if (joined) --total;
        words[2 * s] = std::uint32_t(total) | (joined ? kJoinedBit : 0u);
        const std::uint32_t v0 = lines.segmentVertices[2 * s];
        const glm::vec3 a(lines.positionRadius[v0]);
        const glm::vec3 b(lines.positionRadius[lines.segmentVertices[2 * s + 1]]);
        const float length = glm::length(b - a);
        const glm::vec3 axis = segmentAxis(a, b);
        glm::vec3 t, bt;
        tangentFrame(axis, t, bt);
        // A polyline's first segment starts a frame, unless the polyline is a run cut from a
        // longer one (a rank's share of data-parallel rendering): then it carries on the tangent
        // the source polyline brought to the cut.
        glm::vec3 previous(0.0f);
        if (joined)
            previous = transported;
        else if (!lines.incomingTangent.empty())
            previous = lines.incomingTangent[lines.polylineId[v0]];
        transported = transportTangent(previous, axis, t);
        const float origin = std::atan2(glm::dot(transported, bt), glm::dot(transported, t));
        std::memcpy(&words[2 * s + 1], &origin, sizeof(float));
        const float steps = std::ceil(length / spacing);
        total += std::size_t(std::clamp(steps + 1.0f, 2.0f, float(kMaxSamplesPerSegment)));
        TC_CHECK(total < kJoinedBit);  // sample indices below the flag bit
    }
    words[2 * segments] = std::uint32_t(total);
    TC_CHECK(total * (kAzimuths / 4) < (std::size_t(1) << 31));  // uint word indices in the shaders
    cache.m_sampleCount = total;
    cache.m_offsets = makeBuffer(words.size() * sizeof(std::uint32_t), words.data());
    cache.m_samples = makeBuffer(std::size_t(kAzimuths / 4) * total * sizeof(std::uint32_t));

    // AO_LINE_CACHE too: the shader library's include-once expansion ignores #ifdef, so the
    // conditional include of ao_line_cache.glsl in ambient_occlusion.glsl must be the live one.
    const Program program = compileProgram({{GL_COMPUTE_SHADER, "ao_line_cache_build.comp"}},
                                           {"AMBIENT_OCCLUSION", "AO_LINES", "AO_LINE_CACHE", define()});
    const GLuint p = program.id();
    setAoUniforms(p);
    geometry.bind();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kAoCacheSegments, cache.m_offsets.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kAoCacheOut, cache.m_samples.id());
    glUseProgram(p);
    glProgramUniform1ui(p, uniformLocation(p, "uSegmentCount"), GLuint(segments));
    dispatchItems(p, "uFirstSegment", 0, segments, 64);  // shaders/ao_line_cache_build.comp local_size_x
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glFinish();
    cache.m_buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    cache.m_buildCpuMs = 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC;
    return cache;
}

void AoLineCache::bind() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kAoCache, m_samples.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kAoCacheSegments, m_offsets.id());
}

nlohmann::json AoLineCache::describe() const {
    return {{"method", "exact cone traced AO cached per segment sample x " + std::to_string(kAzimuths) +
                           " azimuths, interpolated per fragment"},
            {"samples", m_sampleCount},
            {"sample_spacing_world", m_spacing},
            {"cache_mb", double(m_sampleCount * kAzimuths) / (1024.0 * 1024.0)},
            {"build_ms", m_buildMs},
            {"build_cpu_ms", m_buildCpuMs}};
}

}  // namespace tc::gl
