#include "rt/raytraced_particles.h"

#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/shading.h"
#include "core/sphere_glyph.h"
#include "rt/hit_collector.h"
#include "rt/techniques.h"

namespace tc::rt {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The context filter of transparent particle rays: a sphere counts once, at its entry. Embree
// reports both the entry (front-facing) and the exit of a sphere; the exit counts only when the
// ray starts inside the sphere, and then sorts at 0 (core/sphere_glyph.h clamps tNear to 0).
void collectEntry(const RTCFilterFunctionNArguments* args) {
    if (args->valid[0] == 0) return;
    HitCollector& c = HitCollector::of(args);
    const RTCRay* ray = reinterpret_cast<const RTCRay*>(args->ray);
    RayHitRecord h = hitRecordOf(args);
    const glm::vec3 origin(ray->org_x, ray->org_y, ray->org_z);
    if (h.back) {
        h.back = 0;  // an exit counted as the entry of a sphere the eye is in
        const glm::vec4& cr = static_cast<const glm::vec4*>(c.user)[h.prim];
        const glm::vec3 d = origin - glm::vec3(cr);
        if (!(glm::dot(d, d) < cr.w * cr.w)) {
            args->valid[0] = 0;
            return;
        }
        h.t = 0.0f;
    }
    if (!c.offer(h)) args->valid[0] = 0;
}

void throwOnError(RTCDevice device, const char* what) {
    RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
        throw Error(ExitCode::Internal,
                    std::string("Embree: ") + what + " failed with error " + std::to_string(int(e)));
}

}  // namespace

struct RaytracedParticles::Bvh {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    double buildMs = 0;
    ~Bvh() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

RaytracedParticles::~RaytracedParticles() = default;

std::unique_ptr<RaytracedParticles> RaytracedParticles::create(const Scene& scene, const StyledParticles& particles,
                                                               const RegionSetup& region) {
    std::unique_ptr<RaytracedParticles> r(new RaytracedParticles());
    r->m_region = region;
    const RenderSpec& rs = scene.render;
    requireTechnique(raytracedTechnique(), scene, DataKind::Particles);
    r->m_transparent = rs.transparency != Transparency::Opaque;
    r->m_spheres = rs.spheres;
    r->m_lighting = scene.lighting;
    r->m_aovs = scene.output.keptAovs();
    r->m_alphaCutoff = rs.raytracedAlphaCutoff;
    if (rs.ao.enabled) r->m_aoSpec = rs.ao;
    r->m_bvh = std::make_unique<Bvh>();
    r->m_bvh->device = rtcNewDevice(nullptr);
    if (!r->m_bvh->device) throw Error(ExitCode::Internal, "Embree: rtcNewDevice failed (unsupported CPU?)");
    r->upload(particles);
    return r;
}

void RaytracedParticles::upload(const StyledParticles& particles) {
    m_ambient.reset();  // refers to the particles and the scene replaced here
    m_particles = particles;
    auto t0 = std::chrono::steady_clock::now();
    if (m_bvh->scene) rtcReleaseScene(m_bvh->scene);
    m_bvh->scene = rtcNewScene(m_bvh->device);
    rtcSetSceneFlags(m_bvh->scene, m_transparent ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(m_bvh->scene, RTC_BUILD_QUALITY_MEDIUM);
    if (particles.size() > 0) {
        RTCGeometry geom = rtcNewGeometry(m_bvh->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<glm::vec4*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                                  sizeof(glm::vec4), particles.size()));
        std::memcpy(v, particles.centerRadius.data(), particles.size() * sizeof(glm::vec4));
        rtcCommitGeometry(geom);
        rtcAttachGeometry(m_bvh->scene, geom);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(m_bvh->scene);
    throwOnError(m_bvh->device, "building the particle BVH");
    m_bvh->buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // Per data frame, as the GL sphere renderer re-voxelizes (after the BVH: ray_traced uses it).
    if (m_aoSpec)
        m_ambient = std::make_unique<ParticleAmbient>(*m_aoSpec, m_spheres, !m_transparent, m_particles, m_bvh->scene,
                                                      m_region);
}

SceneBounds RaytracedParticles::traceBounds() const {
    SceneBounds bounds = sceneBounds(m_bvh->scene);
    if (m_region.clips()) {
        // As the tubes (rt/raytraced_renderer.cpp): tiles that cannot meet the region's part of
        // the spheres are background.
        const RegionBox& region = m_region.box;
        const glm::vec3 pad = 1e-5f * (glm::abs(region.lo) + glm::abs(region.hi)) + 1e-30f;
        bounds.lo = glm::max(bounds.lo, region.lo - pad);
        bounds.hi = glm::min(bounds.hi, region.hi + pad);
    }
    return bounds;
}

RayInterval RaytracedParticles::regionRayInterval(const Ray& ray) const {
    RayInterval iv = rayInterval(ray, m_region.box);
    // A margin for the rounding of hit points on a face; RegionBox::contains decides.
    if (!iv.empty()) iv = {iv.t0 - 1e-5f * std::abs(iv.t0), iv.t1 + 1e-5f * std::abs(iv.t1)};
    return iv;
}

std::uint64_t RaytracedParticles::regionFirstHit(const Ray& ray, FirstHit& first) const {
    first.hit = false;
    const RayInterval iv = regionRayInterval(ray);
    if (iv.empty() || iv.t1 < 0.0f) return 0;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::uint64_t hits = 0;
    float tnear = std::max(iv.t0, 0.0f);
    // Each pass starts behind the last sphere, so the loop ends at the box's far side.
    for (;;) {
        RTCRayHit rh = makeRayHit(ray, tnear);
        rh.ray.tfar = iv.t1;
        rtcIntersect1(m_bvh->scene, &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hits;
        ++hits;
        const std::uint32_t i = rh.hit.primID;
        const glm::vec4& cr = m_particles.centerRadius[i];
        const SphereInterval s = intersectSphere(ray, glm::vec3(cr), cr.w);
        const float tEntry = s.hit ? s.tNear : rh.ray.tfar;  // grazing: Embree's, as render() does
        if (m_region.box.contains(ray.origin + tEntry * ray.dir)) {
            first = {true, i, rh.ray.tfar, glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z)};
            return hits;
        }
        tnear = std::nextafter(rh.ray.tfar, kInf);
    }
}

void RaytracedParticles::render(const Camera& camera, int width, int height, FrameImages& out, StageSink& sink,
                                const ImageWindow& window) const {
    sink.begin("raytrace");
    // Every pixel is written below (background: allocate's clear values); unrequested AOVs stay empty.
    out.resize(width, height, m_aovs);
    if (m_ambient && !m_transparent) out.ao.resize(out.pixelCount());
    const glm::vec3 forward = camera.forward();
    const glm::vec3 lightDir = lightDirectionWorld(m_lighting, camera);
    const bool ortho = camera.projection == Projection::Orthographic;
    const float P = densityNormalisation(m_spheres.density, m_spheres.innerRadius);
    const StyledParticles& S = m_particles;
    std::atomic<std::uint64_t> totalHits{0};

    // One sphere along `ray` at entry parameter tNear (the interval from core/sphere_glyph.h, so the
    // numbers are the reference's): the normal at the entry, and the colour it contributes.
    auto entryNormal = [&](const Ray& ray, std::uint32_t i, float tNear) {
        const glm::vec4& cr = S.centerRadius[i];
        return (ray.origin + tNear * ray.dir - glm::vec3(cr)) / cr.w;
    };

    // A_O and L_A at the entry point (shaders/sphere.frag): none without render.ao.
    auto ambientAt = [&](std::uint32_t i, const Ray& ray, float tNear, const glm::vec3& n, std::size_t pixel) {
        if (!m_ambient) return AmbientTerms{};
        return m_ambient->at(i, ray.origin + tNear * ray.dir, n, std::uint32_t(pixel));
    };

    const RegionBox& region = m_region.box;
    const bool clips = m_region.clips();
    const SceneBounds bounds = traceBounds();

    forEachTile(
        camera, window, width, height,
        [&](const Tile& tile) {
            if (tile.outside) return storeBackground(out, tile, width);
            std::uint64_t hits = 0;
            FirstHit firstHits[kTile * kTile];
            if (!m_transparent && !clips) traceFirstHits(m_bvh->scene, m_traversal, tile, firstHits);
            if (!m_transparent && clips)
                for (int k = 0; k < tile.count(); ++k) hits += regionFirstHit(tile.rays[k], firstHits[k]);
            HitCollector collector;
            rtcInitIntersectContext(&collector.context);
            collector.context.filter = collectEntry;
            collector.capacity = hitsPerPass(m_alphaCutoff);
            collector.user = S.centerRadius.data();
            for (int k = 0; k < tile.count(); ++k) {
                const Ray& ray = tile.rays[k];
                const std::size_t pixel = std::size_t(tile.py(k)) * std::size_t(width) + std::size_t(tile.px(k));
                const float depthScale = ortho ? 1.0f : glm::dot(ray.dir, forward);
                storePixel(out, pixel, glm::vec4(0.0f), kInf, glm::vec3(0.0f), kBackgroundId);
                if (!m_transparent) {
                    float ao = 1.0f;
                    if (firstHits[k].hit) {
                        const std::uint32_t i = firstHits[k].prim;
                        const glm::vec4& cr = S.centerRadius[i];
                        const SphereInterval s = intersectSphere(ray, glm::vec3(cr), cr.w);
                        // Grazing: Embree hit what the exact test calls a miss; keep Embree's distance.
                        const float tNear = s.hit ? s.tNear : firstHits[k].t;
                        const glm::vec3 n = entryNormal(ray, i, tNear);
                        const AmbientTerms amb = ambientAt(i, ray, tNear, n, pixel);
                        ao = amb.ao;
                        // As shaders/sphere.frag (OPAQUE): alpha_A only with AO.
                        const glm::vec3 e =
                            sphereEmission(glm::vec3(S.color[i]), n, ray.dir, lightDir, m_lighting, 0.0f,
                                           m_ambient ? m_spheres.alphaA : 0.0f, amb.ao, amb.light);
                        storePixel(out, pixel, glm::vec4(e, 1.0f), tNear * depthScale, n, S.id[i]);
                        ++hits;
                    }
                    if (!out.ao.empty()) out.ao[pixel] = ao;
                    continue;
                }
                glm::vec4 acc(0.0f);
                bool first = true, done = false;
                float tnear = 0.0f, tfar = kInf;
                if (clips) {
                    const RayInterval iv = regionRayInterval(ray);
                    done = iv.empty() || iv.t1 < 0.0f;
                    tnear = std::max(iv.t0, 0.0f);
                    tfar = iv.t1;
                }
                collector.haveLast = false;
                while (!done) {
                    const int n = collector.trace(m_bvh->scene, ray, tnear, tfar);
                    for (int h = 0; h < n && !done; ++h) {
                        ++hits;
                        const std::uint32_t i = collector.hits[h].prim;
                        const glm::vec4& cr = S.centerRadius[i];
                        const glm::vec4& col = S.color[i];
                        const SphereInterval s = intersectSphere(ray, glm::vec3(cr), cr.w);
                        if (!s.hit) continue;  // grazing: no optical depth
                        if (clips && !region.contains(ray.origin + s.tNear * ray.dir)) continue;  // another region's
                        const float alpha = sphereOpacity(
                            col.w, unitOpticalDepth(m_spheres.density, m_spheres.innerRadius, s, cr.w), P);
                        const glm::vec3 nrm = entryNormal(ray, i, s.tNear);
                        const AmbientTerms amb = ambientAt(i, ray, s.tNear, nrm, pixel);
                        const glm::vec3 e = sphereEmission(glm::vec3(col), nrm, ray.dir, lightDir, m_lighting,
                                                           m_spheres.alphaRv, m_spheres.alphaA, amb.ao, amb.light);
                        if (first) {
                            first = false;
                            storeAovs(out, pixel, s.tNear * depthScale, nrm, S.id[i]);
                        }
                        // "Under", as the reference and the GPU's blending of premultiplied colour.
                        const float w = 1.0f - acc.w;
                        acc += glm::vec4(w * (alpha * e), w * alpha);
                        if (m_alphaCutoff < 1.0f && acc.w >= m_alphaCutoff) done = true;
                    }
                    if (n < collector.capacity) break;
                    if (!done) tnear = collector.continueBehindLast();
                }
                for (int c = 0; c < 4; ++c) out.rgba[4 * pixel + std::size_t(c)] = acc[c];
            }
            totalHits += hits;
        },
        &bounds);
    m_lastHits = totalHits.load();
    sink.setItems(m_lastHits);
    sink.end();
}

nlohmann::json RaytracedParticles::describe() const {
    nlohmann::json j = {{"technique", "raytraced"},
                        {"engine", "Embree " + std::to_string(RTC_VERSION_MAJOR) + "." +
                                       std::to_string(RTC_VERSION_MINOR) + "." + std::to_string(RTC_VERSION_PATCH)},
                        {"geometry", "RTC_GEOMETRY_TYPE_SPHERE_POINT"},
                        {"transparency", m_transparent ? "raytraced front-to-back, emission-absorption" : "opaque"},
                        {"tile", kTile},
                        {"traversal", traversalName(m_traversal)},
                        {"threads", tbb::this_task_arena::max_concurrency()},
                        {"particles", m_particles.size()},
                        {"bvh_build_ms", m_bvh->buildMs},
                        {"ambient_occlusion", m_ambient ? m_ambient->describe() : nlohmann::json(false)}};
    if (m_transparent) {
        j["alpha_cutoff"] = m_alphaCutoff;
        j["density"] = int(m_spheres.density);
        j["alpha_rv"] = m_spheres.alphaRv;
    }
    return j;
}

}  // namespace tc::rt
