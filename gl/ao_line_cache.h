#pragma once
// Cached line ambient occlusion (render.ao.cache "precomputed"): AO from the density volume does not
// depend on the view, so instead of tracing cones for every shaded fragment (per pixel in the
// opaque deferred pass, per fragment before k-buffer insertion, which on llvmpipe tripled the
// k-buffer frame) the exact cone traced AO is evaluated once per dataset at samples along every
// segment (shared at the joints of a polyline), for 8 normals around its axis, and
// shaders/ao_line_cache.glsl interpolates it per fragment (position along the segment, azimuth of
// the normal). Layout and lookup: that file.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "core/styled_lines.h"
#include "gl/line_geometry.h"
#include "gl/objects.h"

namespace tc::gl {

class AoLineCache {
public:
    // Normals cached around each segment's axis (unorm8 each, 4 per word): AO_CACHE_AZIMUTHS.
    static constexpr int kAzimuths = 8;
    static std::string define() { return "AO_CACHE_AZIMUTHS " + std::to_string(kAzimuths); }

    // Samples per segment: one every `spacing` world units along it, at least its two ends, at
    // most kMaxSamplesPerSegment. Needs a current context; `setAoUniforms` binds the density
    // volume and sets the cone tracing uniforms of the build program (AmbientOcclusion::apply).
    static constexpr int kMaxSamplesPerSegment = 64;
    // Offsets word flag: the segment starts at the previous segment's end and shares its sample
    // there (AO_CACHE_JOINED_BIT in shaders/ao_line_cache.glsl).
    static constexpr std::uint32_t kJoinedBit = 0x80000000u;
    static AoLineCache build(const LineGeometry& geometry, const StyledLines& lines, float spacing,
                             const std::function<void(GLuint)>& setAoUniforms);

    // Binds the cache SSBOs (binding::kAoCache, binding::kAoCacheSegments).
    void bind() const;
    nlohmann::json describe() const;

private:
    Buffer m_samples, m_offsets;
    std::size_t m_sampleCount = 0;
    float m_spacing = 0;
    double m_buildMs = 0, m_buildCpuMs = 0;  // wall, process CPU (all threads)
};

}  // namespace tc::gl
