#include "rt/particle_ambient.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <limits>

#include "core/camera.h"
#include "core/error.h"
#include "core/sphere_glyph.h"
#include "core/tangent_frame.h"
#include "rt/ray_traced_ao.h"

namespace tc::rt {
namespace {

// GLSL packUnorm4x8 / unpackUnorm4x8 (other names: glm has its own, found by ADL).
std::uint32_t packUnorm8x4(const glm::vec4& v) {
    std::uint32_t r = 0;
    for (int c = 0; c < 4; ++c) r |= std::uint32_t(std::lround(std::clamp(v[c], 0.0f, 1.0f) * 255.0f)) << (8 * c);
    return r;
}
glm::vec4 unpackUnorm8x4(std::uint32_t v) {
    return glm::vec4(float(v & 0xFFu), float((v >> 8) & 0xFFu), float((v >> 16) & 0xFFu), float(v >> 24)) / 255.0f;
}

const glm::vec3 kFaceNormals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

}  // namespace

// --- SphereVolume ------------------------------------------------------------------------------

SphereVolume::SphereVolume(const AoSpec& spec, const StyledParticles& particles, const RegionSetup& region,
                           const AmbientTransfer& transfer) {
    // The grid of gl::SphereAmbient::voxelize: spec.resolution cubic voxels along the longest axis
    // of the spheres' bounds, from bounds.lo.
    const Bounds& bounds = region.boundsOr(particles.bounds);
    const RegionBox owner = region.densityOwner();
    const glm::vec3 extent = bounds.empty() ? glm::vec3(1.0f) : glm::max(bounds.extent(), glm::vec3(1e-6f));
    const float longest = std::max({extent.x, extent.y, extent.z});
    const float voxel = longest / float(spec.resolution);
    const glm::ivec3 size =
        glm::clamp(glm::ivec3(glm::ceil(extent / voxel)), glm::ivec3(1), glm::ivec3(spec.resolution));
    m_origin = bounds.empty() ? glm::vec3(0.0f) : bounds.lo;
    m_voxelSize = voxel;
    const std::size_t voxels = std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z);

    // shaders/sphere_voxelize.comp: the overlap weight of Staib et al. 2015, Sect. 5.1 (a sphere
    // inside one voxel: its volume fraction; a voxel inside the sphere: 1; else 3x3x3 sub-samples)
    // in fixed point, summed in 64-bit integers with atomic adds (associative, so the grid does not
    // depend on the thread count or schedule).
    constexpr std::uint32_t kUnitsPerSample = 65536u;
    constexpr std::uint32_t kFullCoverage = 27u * kUnitsPerSample;
    constexpr float kSphereVolume = 4.18879020f;  // 4/3 pi
    std::vector<std::uint64_t> acc(4 * voxels, 0u);
    const glm::vec3 origin = m_origin;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, particles.size(), 1024), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const glm::vec4 cr = particles.centerRadius[i];
            if (!owner.contains(glm::vec3(cr))) continue;
            const glm::vec4 color =
                glm::clamp(ambientClassify(transfer, glm::clamp(particles.color[i], glm::vec4(0.0f), glm::vec4(1.0f))),
                           glm::vec4(0.0f), glm::vec4(1.0f));
            const std::uint32_t opacity = std::uint32_t(std::round(color.w * 255.0f));
            if (opacity == 0u) continue;
            const glm::uvec3 rgb(glm::round(glm::vec3(color) * 255.0f));
            const glm::vec3 c = (glm::vec3(cr) - origin) / voxel;
            const float r = cr.w / voxel;
            const float r2 = r * r;
            const glm::ivec3 lo = glm::max(glm::ivec3(glm::floor(c - r)), glm::ivec3(0));
            const glm::ivec3 hi = glm::min(glm::ivec3(glm::floor(c + r)), size - 1);
            for (int z = lo.z; z <= hi.z; ++z)
                for (int y = lo.y; y <= hi.y; ++y)
                    for (int x = lo.x; x <= hi.x; ++x) {
                        const glm::vec3 vlo{float(x), float(y), float(z)};
                        const glm::vec3 vhi = vlo + 1.0f;
                        const glm::vec3 nearest = glm::clamp(c, vlo, vhi) - c;
                        if (glm::dot(nearest, nearest) >= r2) continue;
                        const glm::vec3 farthest = glm::max(glm::abs(vlo - c), glm::abs(vhi - c));
                        std::uint32_t w = kFullCoverage;
                        if (glm::all(glm::greaterThanEqual(c - r, vlo)) && glm::all(glm::lessThanEqual(c + r, vhi))) {
                            // nearbyint: round half to even, as GLSL roundEven.
                            w = std::uint32_t(std::nearbyint(kSphereVolume * r * r * r * float(kFullCoverage)));
                        } else if (glm::dot(farthest, farthest) > r2) {
                            std::uint32_t n = 0u;
                            for (int k = 0; k < 27; ++k) {
                                const glm::vec3 s =
                                    vlo + (glm::vec3(float(k % 3), float((k / 3) % 3), float(k / 9)) + 0.5f) / 3.0f - c;
                                n += glm::dot(s, s) < r2 ? 1u : 0u;
                            }
                            w = n * kUnitsPerSample;
                        }
                        if (w == 0u) continue;
                        const std::size_t v =
                            4 * (std::size_t(x) +
                                 std::size_t(size.x) * (std::size_t(y) + std::size_t(size.y) * std::size_t(z)));
                        const std::uint64_t wo = std::uint64_t(w) * opacity;
                        std::atomic_ref<std::uint64_t>(acc[v + 0]).fetch_add(wo * rgb.x, std::memory_order_relaxed);
                        std::atomic_ref<std::uint64_t>(acc[v + 1]).fetch_add(wo * rgb.y, std::memory_order_relaxed);
                        std::atomic_ref<std::uint64_t>(acc[v + 2]).fetch_add(wo * rgb.z, std::memory_order_relaxed);
                        std::atomic_ref<std::uint64_t>(acc[v + 3]).fetch_add(wo, std::memory_order_relaxed);
                    }
        }
    });
    // shaders/sphere_volume_resolve.comp: the quotient in double, rounded to float.
    const double rgbScale = double(kFullCoverage) * 255.0 * 255.0, alphaScale = double(kFullCoverage) * 255.0;
    std::vector<glm::vec4> level0(voxels);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels, 4096), [&](const auto& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v)
            level0[v] = glm::vec4(float(double(acc[4 * v]) / rgbScale), float(double(acc[4 * v + 1]) / rgbScale),
                                  float(double(acc[4 * v + 2]) / rgbScale), float(double(acc[4 * v + 3]) / alphaScale));
    });
    acc = {};
    if (region.reduceDensity) {
        // Level 0 is linear in the deposits: the ranks' levels sum to the level of all spheres.
        std::vector<float> flat(4 * voxels);
        for (std::size_t v = 0; v < voxels; ++v)
            for (int c = 0; c < 4; ++c) flat[4 * v + std::size_t(c)] = level0[v][c];
        region.reduceDensity(flat);
        TC_CHECK_OP(flat.size(), ==, 4 * voxels);
        for (std::size_t v = 0; v < voxels; ++v)
            for (int c = 0; c < 4; ++c) level0[v][c] = flat[4 * v + std::size_t(c)];
    }
    // shaders/density_mip.comp with MIP_RGBA (same taps and summation order).
    m_mip = MipPyramid<glm::vec4>(size, std::move(level0));
}

// --- ParticleAmbient ---------------------------------------------------------------------------

ParticleAmbient::ParticleAmbient(const AoSpec& spec, const SpheresSpec& spheres, bool opaque,
                                 const StyledParticles& particles, RTCScene scene, const RegionSetup& region)
    : m_spec(spec), m_spheres(spheres), m_opaque(opaque), m_particles(particles), m_scene(scene) {
    auto t0 = std::chrono::steady_clock::now();
    const Bounds& b = region.boundsOr(particles.bounds);
    const glm::vec3 extent = b.empty() ? glm::vec3(1.0f) : glm::max(b.extent(), glm::vec3(1e-6f));
    m_distance = spec.distance * glm::length(extent);  // as gl::SphereAmbient
    if (spec.method == AoSpec::Method::ConeTraced) {
        m_volume = std::make_unique<SphereVolume>(spec, particles, region, spheres.ambient);
        // gl::SphereAmbient::apply: the shaded sphere deposited itself around the point.
        m_startOffset = 1.5f * m_volume->voxelSize();
        if (spec.cache == AoSpec::Cache::Precomputed) {
            const std::size_t n = particles.size();
            m_cube.reset(new std::atomic<std::uint32_t>[6 * n]);
            m_cubeReady.reset(new std::atomic<std::uint8_t>[n]);
            for (std::size_t i = 0; i < n; ++i) m_cubeReady[i].store(0, std::memory_order_relaxed);
        }
    }
    m_buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

ParticleAmbient::~ParticleAmbient() = default;

AmbientTerms ParticleAmbient::at(std::uint32_t sphere, const glm::vec3& p, const glm::vec3& n,
                                 std::uint32_t pixel) const {
    if (m_spec.method == AoSpec::Method::RayTraced) return rayTraced(p, n, pixel);
    if (m_cube) return cached(sphere, n);
    return coneTraced(p, n);
}

AmbientTerms ParticleAmbient::coneTraced(const glm::vec3& p, const glm::vec3& n) const {
    const SphereVolume& v = *m_volume;
    const float vs = v.voxelSize();
    const float maxLod = float(std::max(v.levels() - 1, 0));
    const glm::vec3 scale = 1.0f / (vs * glm::vec3(v.size()));
    const float tanHalf = std::tan(0.5f * glm::radians(m_spec.apertureDeg));
    // traceSphereCone of shaders/sphere_ambient.glsl.
    auto trace = [&](const glm::vec3& dir, float& occlusion, glm::vec3& light) {
        occlusion = 0.0f;
        light = glm::vec3(0.0f);
        float t = m_startOffset;
        for (int i = 0; i < 128 && t < m_distance && occlusion <= 0.99f; ++i) {
            const float diameter = std::max(2.0f * t * tanHalf, vs);
            const float stepLength = std::min(diameter, m_distance - t);
            const float lod = glm::clamp(std::log2(diameter / vs), 0.0f, maxLod);
            const glm::vec4 s = v.textureLod((p + (t + 0.5f * stepLength) * dir - v.origin()) * scale, lod);
            const float a = glm::clamp(s.w, 0.0f, 1.0f);
            const float alpha =
                1.0f - std::exp2(m_spec.strength * stepLength / vs * std::log2(std::max(1.0f - a, 1e-30f)));
            const glm::vec3 color = s.w > 1e-6f ? glm::clamp(glm::vec3(s) / s.w, 0.0f, 1.0f) : glm::vec3(0.0f);
            light += (1.0f - occlusion) * alpha * color;
            occlusion += (1.0f - occlusion) * alpha;
            t += stepLength;
        }
    };
    // sphereAmbient.
    glm::vec3 tangent, bitangent;
    tangentFrame(n, tangent, bitangent);
    const int cones = m_spec.cones;
    const bool central = cones == 1 || cones >= 6;
    const int ringCones = central ? cones - 1 : cones;
    const float ringPolar = cones >= 6 ? glm::radians(60.0f) : glm::radians(45.0f);
    const float ringCos = std::cos(ringPolar), ringSin = std::sin(ringPolar);
    float visible = 0.0f, weightSum = 0.0f;
    AmbientTerms r;
    float occ;
    glm::vec3 light;
    if (central) {
        trace(n, occ, light);
        visible += 1.0f - occ;
        r.light += light;
        weightSum += 1.0f;
    }
    for (int i = 0; i < ringCones; ++i) {
        const float phi = 6.28318530718f * float(i) / float(ringCones);
        const glm::vec3 dir = ringCos * n + ringSin * (std::cos(phi) * tangent + std::sin(phi) * bitangent);
        trace(dir, occ, light);
        visible += ringCos * (1.0f - occ);
        r.light += ringCos * light;
        weightSum += ringCos;
    }
    if (weightSum > 0.0f) {
        r.ao = visible / weightSum;
        r.light /= weightSum;
    }
    return r;
}

AmbientTerms ParticleAmbient::cached(std::uint32_t sphere, const glm::vec3& n) const {
    std::atomic<std::uint32_t>* cube = &m_cube[6 * std::size_t(sphere)];
    if (m_cubeReady[sphere].load(std::memory_order_acquire) == 0) {
        // shaders/sphere_ambient_cache.comp for this sphere's six faces.
        const glm::vec4 cr = m_particles.centerRadius[sphere];
        for (int f = 0; f < 6; ++f) {
            const AmbientTerms t = coneTraced(glm::vec3(cr) + cr.w * kFaceNormals[f], kFaceNormals[f]);
            cube[f].store(packUnorm8x4(glm::vec4(t.light, t.ao)), std::memory_order_relaxed);
        }
        m_cubeReady[sphere].store(1, std::memory_order_release);
    }
    // sphereAmbientCached of shaders/sphere_ambient.glsl.
    const glm::vec3 w = n * n;
    const int fx = n.x < 0.0f ? 1 : 0, fy = n.y < 0.0f ? 3 : 2, fz = n.z < 0.0f ? 5 : 4;
    const glm::vec4 v = w.x * unpackUnorm8x4(cube[fx].load(std::memory_order_relaxed)) +
                        w.y * unpackUnorm8x4(cube[fy].load(std::memory_order_relaxed)) +
                        w.z * unpackUnorm8x4(cube[fz].load(std::memory_order_relaxed));
    return {v.w, glm::vec3(v)};
}

AmbientTerms ParticleAmbient::rayTraced(const glm::vec3& p, const glm::vec3& n, std::uint32_t pixel) const {
    // Off the surface by a small fraction of the radius (as rt/ray_traced_ao.cpp).
    const glm::vec3 origin = p + (1e-3f * std::max(m_particles.maxRadius, 1e-12f) + 1e-6f * glm::length(p)) * n;
    const float P = densityNormalisation(m_spheres.density, m_spheres.innerRadius);
    const int m = std::max(1, int(std::lround(std::sqrt(double(m_spec.samples)))));
    float blocked = 0.0f;
    glm::vec3 light(0.0f);
    traceHemisphereRays(m_scene, origin, n, pixel, m, m_distance, [&](const RTCRayHit& rh, const glm::vec3& dir) {
        const std::uint32_t s = rh.hit.primID;
        const glm::vec4 cr = m_particles.centerRadius[s];
        // The ambient transfer functions give the sphere's opacity and colour for these rays.
        const glm::vec4 col = ambientClassify(m_spheres.ambient, m_particles.color[s]);
        float a = col.w;
        if (!m_opaque) {
            const SphereInterval iv = intersectSphere(Ray{origin, dir}, glm::vec3(cr), cr.w);
            a = iv.hit ? sphereOpacity(col.w, unitOpticalDepth(m_spheres.density, m_spheres.innerRadius, iv, cr.w), P)
                       : 0.0f;
        }
        blocked += a;
        light += a * glm::clamp(glm::vec3(col), 0.0f, 1.0f);
    });
    const float inv = 1.0f / float(m * m);
    return {std::pow(std::max(1.0f - blocked * inv, 0.0f), m_spec.strength), light * inv};
}

nlohmann::json ParticleAmbient::describe() const {
    if (m_spec.method == AoSpec::Method::RayTraced)
        return {{"method", "ray traced hemisphere (Embree spheres), A_O and L_A"},
                {"samples", int(std::pow(std::max(1L, std::lround(std::sqrt(double(m_spec.samples)))), 2))},
                {"distance_world", m_distance},
                {"strength", m_spec.strength}};
    const glm::ivec3 s = m_volume->size();
    return {{"method", "voxel cone tracing of a CPU sphere voxelization (RGBA: coverage x opacity, colour)"},
            {"size", {s.x, s.y, s.z}},
            {"voxel_size", m_volume->voxelSize()},
            {"levels", m_volume->levels()},
            {"cones", m_spec.cones},
            {"aperture_deg", m_spec.apertureDeg},
            {"distance_world", m_distance},
            {"strength", m_spec.strength},
            {"ambient_transfer", describeAmbientTransfer(m_spheres.ambient)},
            {"cache", m_cube ? "ambient cube per sphere, filled when a ray first hits the sphere" : "none"},
            {"voxelize_and_mips_ms", m_buildMs},
            {"volume_mb", double(m_volume->bytes()) / (1024.0 * 1024.0)}};
}

}  // namespace tc::rt
