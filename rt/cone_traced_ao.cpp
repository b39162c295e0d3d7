#include "rt/cone_traced_ao.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "core/error.h"
#include "core/tangent_frame.h"

namespace tc::rt {
namespace {

constexpr float kConeOcclusionCutoff = 0.99f;
constexpr int kConeMaxSteps = 128;

float coneDensity(const DensityPyramid& v, glm::vec3 p, float lod) {
    const glm::vec3 uvw = (p - v.origin()) / (v.voxelSize() * glm::vec3(v.size()));
    return v.textureLod(uvw, lod);
}

glm::vec3 texelWidth(const DensityPyramid& v, int level) {
    return glm::vec3(v.size()) / glm::vec3(glm::max(v.size() >> level, glm::ivec3(1)));
}

constexpr float kConeOwnMargin = 1.001f;
constexpr float kConeOwnSlack = 1e-3f;

float coneLevelDensityExcluding(const DensityPyramid& v, glm::vec3 pv, int level, glm::vec3 o, glm::vec3 invU,
                                float ownDensity) {
    const glm::ivec3 n = v.levelSize(level);
    const glm::vec3 w = glm::vec3(v.size()) / glm::vec3(n);
    const glm::vec3 c = pv / w - 0.5f;
    const glm::vec3 base = glm::floor(c);
    const glm::vec3 f = c - base;
    const glm::ivec3 i0(base);
    const float perLength = ownDensity / (w.x * w.y * w.z);
    const glm::vec3 lo0 = base * w - kConeOwnSlack, hi0 = lo0 + w + 2.0f * kConeOwnSlack;
    const glm::vec3 a0 = (lo0 - o) * invU, b0 = (hi0 - o) * invU, a1 = (lo0 + w - o) * invU, b1 = (hi0 + w - o) * invU;
    const glm::vec3 near0 = glm::min(a0, b0), far0 = glm::max(a0, b0), near1 = glm::min(a1, b1),
                    far1 = glm::max(a1, b1);
    float sum = 0.0f;
    for (int k = 0; k < 8; ++k) {
        const glm::ivec3 d(k & 1, (k >> 1) & 1, k >> 2);
        const glm::ivec3 i = i0 + d;
        if (glm::any(glm::lessThan(i, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(i, n))) continue;
        const glm::vec3 w3 = glm::mix(1.0f - f, f, glm::vec3(d));
        glm::vec3 tNear, tFar;
        for (int a = 0; a < 3; ++a) {
            tNear[a] = d[a] ? near1[a] : near0[a];
            tFar[a] = d[a] ? far1[a] : far0[a];
        }
        const float len = std::max(std::min({tFar.x, tFar.y, tFar.z}) - std::max({tNear.x, tNear.y, tNear.z}), 0.0f);
        const float texel = v.texel(level, i.x, i.y, i.z);
        sum += w3.x * w3.y * w3.z * std::max(texel - perLength * len, 0.0f);
    }
    return sum;
}

float coneDensityExcluding(const DensityPyramid& v, glm::vec3 p, float lod, const ConeOwnTube& own) {
    if (!(own.density > 0.0f)) return coneDensity(v, p, lod);
    const int l0 = int(std::floor(lod));
    const int l1 = std::min(l0 + 1, std::max(v.levels() - 1, 0));
    const float frac = lod - float(l0);
    const int reachLevel = frac > 0.0f ? l1 : l0;
    const float vs = v.voxelSize();
    const glm::vec3 pv = (p - v.origin()) / vs;
    const glm::vec3 o = (own.origin - v.origin()) / vs;
    const glm::vec3 rel = pv - o;
    const float dist = glm::length(rel - glm::dot(rel, own.dir) * own.dir);
    if (dist > 1.5f * glm::length(texelWidth(v, reachLevel))) return coneDensity(v, p, lod);
    glm::vec3 invU;
    for (int i = 0; i < 3; ++i) invU[i] = 1.0f / (std::abs(own.dir[i]) < 1e-20f ? 1e-20f : own.dir[i]);
    const float ownDensity = own.density * kConeOwnMargin;
    float rho = coneLevelDensityExcluding(v, pv, l0, o, invU, ownDensity);
    if (frac > 0.0f && l1 != l0) rho = glm::mix(rho, coneLevelDensityExcluding(v, pv, l1, o, invU, ownDensity), frac);
    return rho;
}

}  // namespace

float traceOcclusionCone(const DensityPyramid& v, const ConeTracingParams& prm, glm::vec3 apex, glm::vec3 dir,
                         float tanHalfAperture, const ConeOwnTube& own) {
    const float maxLod = float(std::max(v.levels() - 1, 0));
    const float vs = v.voxelSize();
    float occlusion = 0.0f;
    float t = prm.startOffset;
    for (int i = 0; i < kConeMaxSteps && t < prm.maxDistance && occlusion <= kConeOcclusionCutoff; ++i) {
        const float diameter = std::max(2.0f * t * tanHalfAperture, vs);
        const float stepLength = std::min(diameter, prm.maxDistance - t);
        const float lod = glm::clamp(std::log2(diameter / vs), 0.0f, maxLod);
        const float rho =
            glm::clamp(coneDensityExcluding(v, apex + (t + 0.5f * stepLength) * dir, lod, own), 0.0f, 1.0f);
        const float transmittance = std::exp2(prm.strength * stepLength / vs * std::log2(std::max(1.0f - rho, 1e-30f)));
        occlusion += (1.0f - occlusion) * (1.0f - transmittance);
        t += stepLength;
    }
    return occlusion;
}

ConeOwnTube coneOwnTube(const glm::vec4& a, const glm::vec4& b, float alphaA, float alphaB, float voxelSize) {
    const glm::vec3 d = glm::vec3(b) - glm::vec3(a);
    const float len2 = glm::dot(d, d);
    const float r = std::max(a.w, b.w) / voxelSize;
    ConeOwnTube own;
    own.origin = glm::vec3(a);
    own.dir = len2 > 0.0f ? d / std::sqrt(len2) : glm::vec3(0.0f, 0.0f, 1.0f);
    own.density = len2 > 0.0f ? 3.14159265f * r * r * glm::clamp(std::max(alphaA, alphaB), 0.0f, 1.0f) : 0.0f;
    return own;
}

DensityPyramid::DensityPyramid(DensityGrid grid)
    : m_mip(grid.size, std::move(grid.density)), m_origin(grid.origin), m_voxelSize(grid.voxelSize) {}

float coneTracedOcclusion(const DensityPyramid& volume, const ConeTracingParams& prm, glm::vec3 position,
                          glm::vec3 normal, const ConeOwnTube& own) {
    if (prm.cones <= 0) return 1.0f;
    const glm::vec3 n = glm::normalize(normal);
    glm::vec3 tangent, bitangent;
    const glm::vec3 along = own.dir - glm::dot(own.dir, n) * n;
    if (own.density > 0.0f && glm::dot(along, along) > 0.0625f) {
        tangent = glm::normalize(along);
        bitangent = glm::cross(n, tangent);
    } else {
        tangentFrame(n, tangent, bitangent);
    }
    const float tanHalfAperture = std::tan(0.5f * prm.apertureRad);
    const bool central = prm.cones == 1 || prm.cones >= 6;
    const int ringCones = central ? prm.cones - 1 : prm.cones;
    const float ringPolar = prm.cones >= 6 ? glm::radians(60.0f) : glm::radians(45.0f);
    const float ringCos = std::cos(ringPolar), ringSin = std::sin(ringPolar);
    float visible = 0.0f, weightSum = 0.0f;
    if (central) {
        visible += 1.0f - traceOcclusionCone(volume, prm, position, n, tanHalfAperture, own);
        weightSum += 1.0f;
    }
    for (int i = 0; i < ringCones; ++i) {
        const float phi = 6.28318530718f * float(i) / float(ringCones);
        const glm::vec3 dir = ringCos * n + ringSin * (std::cos(phi) * tangent + std::sin(phi) * bitangent);
        visible += ringCos * (1.0f - traceOcclusionCone(volume, prm, position, dir, tanHalfAperture, own));
        weightSum += ringCos;
    }
    return visible / weightSum;
}

ConeTracedAo::ConeTracedAo(const AoSpec& spec, const StyledLines& lines, const RegionSetup& region)
    : m_lines(&lines), m_volume([&] {
          auto t0 = std::chrono::steady_clock::now();
          // The pyramid is built from the (reduced) finest level, as gl::AmbientOcclusion does.
          DensityPyramid v(buildLineDensity(lines, spec.resolution, region));
          m_buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
          return v;
      }()) {
    // The parameters of gl::AmbientOcclusion::create (gl/ambient_occlusion.cpp explains them).
    m_params.cones = spec.cones;
    m_params.apertureRad = glm::radians(spec.apertureDeg);
    m_params.maxDistance = spec.distance * glm::length(region.boundsOr(lines.bounds).extent());
    m_params.strength = spec.strength;
    m_params.startOffset = m_volume.voxelSize();
}

float ConeTracedAo::visibility(const glm::vec3& p, const glm::vec3& n, std::uint32_t, std::uint32_t segment) const {
    const StyledLines& L = *m_lines;
    const std::uint32_t a = L.segmentVertices[2 * segment], b = L.segmentVertices[2 * segment + 1];
    return coneTracedOcclusion(
        m_volume, m_params, p, n,
        coneOwnTube(L.positionRadius[a], L.positionRadius[b], L.color[a].w, L.color[b].w, m_volume.voxelSize()));
}

nlohmann::json ConeTracedAo::describe() const {
    const glm::ivec3 s = m_volume.size();
    return {{"method", "voxel cone tracing (CPU)"},
            {"grid", {s.x, s.y, s.z}},
            {"voxel_size", m_volume.voxelSize()},
            {"levels", m_volume.levels()},
            {"cones", m_params.cones},
            {"aperture_deg", glm::degrees(m_params.apertureRad)},
            {"distance_world", m_params.maxDistance},
            {"voxelize_and_mips_ms", m_buildMs},
            {"volume_mb", double(m_volume.bytes()) / (1024.0 * 1024.0)}};
}

}  // namespace tc::rt
