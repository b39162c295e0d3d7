#include "rt/raytraced_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/rounded_cone.h"
#include "core/shading.h"
#include "core/transparent_reference.h"
#include "rt/ao_estimator.h"
#include "rt/embree_lines.h"
#include "rt/hit_collector.h"
#include "rt/primary_rays.h"
#include "rt/techniques.h"

namespace tc::rt {
namespace {

// A transparent pass keeps the K = hitsPerPass nearest hits not yet composited (the filter below;
// rt/hit_collector.h); when a pixel needs more, the next pass starts behind the K-th.
constexpr float kInf = std::numeric_limits<float>::infinity();

// The context filter of transparent tube rays (rt/hit_collector.h): every hit, front- or
// back-facing, at its own t.
void collectHit(const RTCFilterFunctionNArguments* args) {
    if (args->valid[0] == 0) return;
    if (!HitCollector::of(args).offer(hitRecordOf(args))) args->valid[0] = 0;
}

// The context filter of halo rays that start outside every grown cone (shadeTransparentHalo):
// only the entries, one per cone the ray passes, name segments; exits take no room in the list.
void collectEntry(const RTCFilterFunctionNArguments* args) {
    if (args->valid[0] == 0) return;
    const RayHitRecord h = hitRecordOf(args);
    if (h.back || !HitCollector::of(args).offer(h)) args->valid[0] = 0;
}

// Whether the part t in [0, tMax] of `ray` stays farther than `radius` from the segment [a, b]: then
// it cannot meet a rounded cone on [a, b] whose radii are at most `radius` (the cone lies in that
// capsule). Closest points of two segments (Ericson, Real-Time Collision Detection, 5.1.9). Any
// pair of points bounds the distance from above, so a pair chosen off the optimum by rounding
// could claim "clear" wrongly; that happens only for nearly parallel segments (the solve divides
// by sin^2 of their angle), which are never claimed clear.
bool rayStopsClearOfCapsule(const Ray& ray, float tMax, const glm::vec3& a, const glm::vec3& b, float radius) {
    const glm::vec3 d1 = tMax * ray.dir, d2 = b - a, r = ray.origin - a;
    const float aa = glm::dot(d1, d1), ee = glm::dot(d2, d2), f = glm::dot(d2, r);
    const float c = glm::dot(d1, r), bb = glm::dot(d1, d2);
    const float denom = aa * ee - bb * bb;
    if (!(aa > 0.0f && ee > 0.0f) || denom <= 1e-3f * aa * ee) return false;  // nearly parallel (< ~1.8 deg)
    float s = glm::clamp((bb * f - c * ee) / denom, 0.0f, 1.0f);
    float t = (bb * s + f) / ee;
    if (t < 0.0f) {
        t = 0.0f;
        s = glm::clamp(-c / aa, 0.0f, 1.0f);
    } else if (t > 1.0f) {
        t = 1.0f;
        s = glm::clamp((bb - c) / aa, 0.0f, 1.0f);
    }
    const glm::vec3 gap = (ray.origin + s * d1) - (a + t * d2);
    return glm::dot(gap, gap) > radius * radius;
}

}  // namespace

struct RaytracedRenderer::PixelContext {
    Ray ray;
    std::uint32_t pixel;
    float depthScale;  // view depth = t * depthScale
    glm::vec3 lightDir;
    // Outputs.
    glm::vec4 rgba{0.0f};
    float depth = kInf;
    glm::vec3 normal{0.0f};
    std::uint32_t id = kBackgroundId;
    float ao = 1.0f;
    std::uint64_t hits = 0;
};

RaytracedRenderer::~RaytracedRenderer() = default;

std::unique_ptr<RaytracedRenderer> RaytracedRenderer::create(const Scene& scene, const StyledLines& lines,
                                                             const RegionSetup& region) {
    std::unique_ptr<RaytracedRenderer> r(new RaytracedRenderer());
    r->m_region = region.box;
    const RenderSpec& rs = scene.render;
    requireTechnique(raytracedTechnique(), scene, DataKind::Lines);
    // Every transparent mode is exact compositing here (up to render.raytraced.alpha_cutoff).
    // Halos are drawn by the transparent path only (the technique's descriptor refuses "opaque").
    if (scene.style.halo.enabled) r->m_halo = lineHalo(scene.style.halo, scene.image.background);
    r->m_transparent = rs.transparency != Transparency::Opaque || r->m_halo;
    r->m_lines = lines;
    const std::size_t segments = lines.segmentCount();
    r->m_segmentPolyline.resize(segments);
    for (std::size_t s = 0; s < segments; ++s) r->m_segmentPolyline[s] = lines.polylineId[lines.segmentVertices[2 * s]];
    r->m_uniformColor = !lines.color.empty() &&
                        std::all_of(lines.color.begin(), lines.color.end(),
                                    [&](const glm::vec4& c) { return glm::vec3(c) == glm::vec3(lines.color[0]); });
    if (r->m_uniformColor) r->m_color = glm::vec3(lines.color[0]);
    r->m_lighting = scene.lighting;
    r->m_aovs = scene.output.keptAovs();
    r->m_alphaCutoff = rs.raytracedAlphaCutoff;
    r->m_exactSurface = rs.raytracedExactSurface;
    if (r->m_transparent) {
        // K from the mean opacity of the vertices (rt/hit_collector.h).
        double opacity = 0;
        for (const glm::vec4& c : lines.color) opacity += c.w;
        r->m_defaultHitsPerPass =
            rt::hitsPerPass(r->m_alphaCutoff, lines.color.empty() ? 1.0f : float(opacity / double(lines.color.size())));
        // Halos: a pass's farthest fragments are composited only once the next pass's hits are in
        // (shadeTransparentHalo), so the pass that reaches the cutoff needs headroom beyond it. On
        // the 1M tornado at opacity 0.3 (1920x1080): K = 48 3,033 ms, K = 28 (the tubes' rule)
        // 3,423 ms, K = 16 3,388 ms; at opacity 0.8 and 1, K = 1 stays fastest (1,371 / 561 ms
        // against 1,617 / 1,490 at K = 16); tubecast_raytraced_bench --hits-per-pass.
        if (r->m_halo && r->m_defaultHitsPerPass > 1)
            r->m_defaultHitsPerPass = std::min(2 * r->m_defaultHitsPerPass, kMaxHitsPerPass);
        r->m_hitsPerPass = r->m_defaultHitsPerPass;
    }
    // Opaque images are the union of the rounded cones either way; joined tubes have fewer surfaces.
    // (Opaque without neighbour flags, each segment a closed rounded cone, traced no faster: same
    // CPU time within noise on the 1M tornado's opaque frames, `scripts/bench/frame_times.sh
    // configs/tornado_1m.json 7 --set render.technique=raytraced`.)
    r->m_joinNeighbours = r->m_transparent ? rs.capClipping : true;
    r->m_capClipping = rs.capClipping;
    // From the whole dataset's largest radius (data-parallel), so every rank and one process test
    // joint duplicates with the same epsilon.
    r->m_jointEpsilon = 1e-3f * std::max(region.maxRadiusOr(lines.maxRadius), 1e-12f);
    if (r->m_halo) {
        // Every segment's grown cone closed on its own: each one the ray passes names a segment
        // whose tube or ring fragment is then computed exactly (shadeTransparentHalo).
        r->m_joinNeighbours = false;
        StyledLines grown = r->m_lines;
        const float scale = 1.0f + r->m_halo->geometry.width;
        for (glm::vec4& v : grown.positionRadius) v.w *= scale;
        grown.maxRadius *= scale;
        grown.bounds = {};
        for (const glm::vec4& v : grown.positionRadius) grown.bounds.extend(glm::vec3(v), v.w);
        r->m_embree = std::make_unique<EmbreeLines>(grown, false, true);
        r->m_cover = TileCover(grown);
        if (rs.ao.enabled && rs.ao.method == AoSpec::Method::RayTraced)
            r->m_aoEmbree = std::make_unique<EmbreeLines>(r->m_lines, true, false);
    } else {
        r->m_embree = std::make_unique<EmbreeLines>(r->m_lines, r->m_joinNeighbours, r->m_transparent);
        r->m_cover = TileCover(r->m_lines);
    }
    r->m_bounds = sceneBounds(r->m_embree->scene());
    if (region.clips()) {
        // Tiles whose rays cannot meet the region's part of the data are background: the box
        // (grown by a little of its coordinates, covering the rounding of hit points) cut with
        // the BVH's bounds. An empty cut makes every tile background (pixelBlockMisses).
        const glm::vec3 pad = 1e-5f * (glm::abs(r->m_region.lo) + glm::abs(r->m_region.hi)) + 1e-30f;
        r->m_bounds.lo = glm::max(r->m_bounds.lo, r->m_region.lo - pad);
        r->m_bounds.hi = glm::min(r->m_bounds.hi, r->m_region.hi + pad);
    }
    if (rs.ao.enabled)
        r->m_ao = makeAoEstimator(rs.ao, r->m_lines, r->m_aoEmbree ? *r->m_aoEmbree : *r->m_embree, region);
    return r;
}

void RaytracedRenderer::render(const Camera& camera, int width, int height, FrameImages& out, StageSink& sink,
                               const ImageWindow& window) const {
    sink.begin("raytrace");
    // Every pixel is written below (background ones with the clear values of
    // FrameImages::allocate), so a target reused across frames is not cleared first.
    out.resize(width, height, m_aovs);
    if (m_ao && !m_transparent) out.ao.resize(out.pixelCount());
    const glm::vec3 forward = camera.forward();
    const glm::vec3 lightDir = lightDirectionWorld(m_lighting, camera);
    const bool ortho = camera.projection == Projection::Orthographic;
    const bool clips = !m_region.unbounded();
    // Opaque: a region always takes the exact surface; with "embree", a frame whose rays may start
    // inside a tube does too (Embree's round curves do not report the inner wall such a ray sees).
    const bool exactSurface =
        !m_transparent && (clips || m_exactSurface || originsMayStartInTubes(camera, window, width, height));
    const bool haloOriginsInside =
        m_halo && originsMayStartInTubes(camera, window, width, height, 1.0f + m_halo->geometry.width);
    std::atomic<std::uint64_t> totalHits{0};

    float* const ao = out.ao.empty() ? nullptr : out.ao.data();
    const std::vector<std::uint8_t> cover = m_cover.tiles(camera, window, width, height, kTile);
    forEachTile(
        camera, window, width, height,
        [&](const Tile& tile) {
            if (tile.outside) return storeBackground(out, tile, width);
            std::uint64_t hits = 0;
            FirstHit firstHits[kTile * kTile];
            // Region opaque rays trace one at a time from the box (regionSurface).
            if (!m_transparent && !clips) traceFirstHits(m_embree->scene(), m_traversal, tile, firstHits);
            for (int row = 0, k = 0; row < tile.h; ++row) {
                const std::uint32_t rowStart =
                    std::uint32_t(tile.y0 + row) * std::uint32_t(width) + std::uint32_t(tile.x0);
                for (int col = 0; col < tile.w; ++col, ++k) {
                    PixelContext c;
                    c.pixel = rowStart + std::uint32_t(col);
                    if (!m_transparent && !clips && !firstHits[k].hit) {
                        // Background: PixelContext's defaults are FrameImages::allocate's clear values.
                        storePixel(out, c.pixel, c.rgba, c.depth, c.normal, c.id);
                        if (ao) ao[c.pixel] = c.ao;
                        continue;
                    }
                    c.ray = tile.rays[k];
                    c.depthScale = ortho ? 1.0f : glm::dot(c.ray.dir, forward);
                    c.lightDir = lightDir;
                    if (m_halo) {
                        shadeTransparentHalo(c, {camera.eye, forward, c.depthScale}, haloOriginsInside);
                    } else if (m_transparent) {
                        shadeTransparent(c);
                    } else if (clips) {
                        Surface s;
                        if (regionSurface(c, s)) shadeSurface(c, s);
                    } else {
                        shadeOpaque(c, firstHits[k], exactSurface);
                    }
                    hits += c.hits;
                    storePixel(out, c.pixel, c.rgba, c.depth, c.normal, c.id);
                    if (ao) ao[c.pixel] = c.ao;
                }
            }
            totalHits += hits;
        },
        &m_bounds, &cover);
    m_lastHits = totalHits.load();
    m_lastExactSurface = exactSurface;
    sink.setItems(m_lastHits);
    sink.end();
}

bool RaytracedRenderer::visibleSurface(const Ray& ray, const FirstHit& hit, bool inRegion, Surface& surface,
                                       bool& anyCandidate) const {
    // Re-intersect the hit segment and its polyline neighbours exactly as the CPU reference does
    // (see the header): Embree's curve intersector solves the same surface with other float
    // operations, and at joints it may attribute a point to either neighbour.
    const StyledLines& L = m_lines;
    const std::uint32_t hitSeg = hit.prim;
    const std::size_t segments = L.segmentCount();
    float best = kInf;
    std::uint32_t bestSeg = hitSeg;
    glm::vec3 bestN(0.0f);
    anyCandidate = false;
    // The CPU reference's rule on one segment: nearest wins, equal t to the lower segment.
    auto consider = [&](std::uint32_t s) {
        const std::uint32_t v0 = L.segmentVertices[2 * s], v1 = L.segmentVertices[2 * s + 1];
        const glm::vec4& a = L.positionRadius[v0];
        const glm::vec4& b = L.positionRadius[v1];
        const auto hit = firstSurfaceHit(ray, {glm::vec3(a), a.w, glm::vec3(b), b.w});
        if (!hit) return;
        const float t = hit->t;
        const glm::vec3 n = hit->normal;
        anyCandidate = true;
        if (inRegion && !m_region.contains(ray.origin + t * ray.dir)) return;
        if (t < best || (t == best && s < bestSeg)) best = t, bestSeg = s, bestN = n;
    };
    consider(hitSeg);
    const std::uint32_t polyline = m_segmentPolyline[hitSeg];
    for (std::uint32_t s : {hitSeg - 1, hitSeg + 1}) {  // hitSeg - 1 wraps past `segments` at 0
        if (s >= segments) continue;
        const std::uint32_t v0 = L.segmentVertices[2 * s], v1 = L.segmentVertices[2 * s + 1];
        if (m_segmentPolyline[s] != polyline) continue;
        if (best != kInf) {
            // Skip a neighbour the ray cannot reach before `best`: its rounded cone lies in the
            // sphere around its midpoint of radius half its length + its larger radius, which the
            // ray enters at tEnter <= any t of the cone. The margin covers the rounding of this
            // bound, so a skipped neighbour could neither win nor tie: images stay identical.
            const glm::vec4& a = L.positionRadius[v0];
            const glm::vec4& b = L.positionRadius[v1];
            const glm::vec3 m = 0.5f * (glm::vec3(a) + glm::vec3(b)) - ray.origin;
            const float R = 0.5f * glm::length(glm::vec3(b) - glm::vec3(a)) + std::max(a.w, b.w);
            const float along = glm::dot(m, ray.dir);
            const float miss2 = glm::dot(m, m) - along * along;
            const float slack = 1e-4f * (std::abs(along) + R + best);
            const float R2 = (R + slack) * (R + slack);
            if (miss2 > R2) continue;
            const float tEnter = along - std::sqrt(R2 - miss2);
            if (tEnter > best + slack) continue;
            if (rayStopsClearOfCapsule(ray, best + slack, glm::vec3(a), glm::vec3(b), std::max(a.w, b.w) + slack))
                continue;
        }
        consider(s);
    }
    if (best == kInf) return false;
    surface = {best, bestSeg, bestN};
    return true;
}

void RaytracedRenderer::shadeOpaque(PixelContext& c, const FirstHit& hit, bool exactSurface) const {
    c.hits = 1;
    Surface s;
    bool anyCandidate = false;
    if (!exactSurface || !visibleSurface(c.ray, hit, false, s, anyCandidate)) {
        // render.raytraced.surface "embree" (or, exact, grazing: Embree hit what the exact
        // intersector calls a miss): Embree's hit as it is.
        s.t = hit.t;
        s.segment = hit.prim;
        s.normal = glm::dot(hit.ng, hit.ng) > 0.0f ? glm::normalize(hit.ng) : -c.ray.dir;
    }
    shadeSurface(c, s);
}

bool RaytracedRenderer::originsMayStartInTubes(const Camera& camera, const ImageWindow& window, int width, int height,
                                               float radiusScale) const {
    // The ray origins: the eye (perspective) or the image rectangle on the plane through it
    // (orthographic), held in the sphere around the eye through the rectangle's corners; with a
    // margin for the rounding of the distances. (Embree's rtcPointQuery visits no curve
    // primitives, so the segments are scanned here, and only when the sphere meets the data's
    // bounds: a camera outside the data costs one box test per frame.)
    const int fw = fullWidthOf(window, width), fh = fullHeightOf(window, height);
    // Corners one pixel beyond the image: sample jitter moves the rays by up to half a pixel.
    float radius = 0.0f;
    for (float px : {-1.5f, float(fw) + 0.5f})
        for (float py : {-1.5f, float(fh) + 0.5f})
            radius = std::max(radius, glm::length(pixelRay(camera, fw, fh, px, py).origin - camera.eye));
    const glm::vec3 eye = camera.eye;
    radius += 1e-4f * (radiusScale * m_lines.maxRadius + glm::length(eye) + radius);
    // The bounds hold every tube; grown ones reach further by the growth of the largest radius.
    const glm::vec3 nearest = glm::clamp(eye, m_lines.bounds.lo, m_lines.bounds.hi);
    const float growth = (radiusScale - 1.0f) * m_lines.maxRadius;
    if (m_lines.bounds.empty() || glm::length(nearest - eye) > radius + growth) return false;
    const StyledLines& L = m_lines;
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, L.segmentCount(), 1 << 14), false,
        [&](const tbb::blocked_range<std::size_t>& range, bool found) {
            for (std::size_t s = range.begin(); !found && s != range.end(); ++s) {
                const glm::vec4& a = L.positionRadius[L.segmentVertices[2 * s]];
                const glm::vec4& b = L.positionRadius[L.segmentVertices[2 * s + 1]];
                // Bounding sphere of the rounded cone first.
                const glm::vec3 m = 0.5f * (glm::vec3(a) + glm::vec3(b));
                const float reach =
                    0.5f * glm::length(glm::vec3(b) - glm::vec3(a)) + radiusScale * std::max(a.w, b.w) + radius;
                if (glm::dot(m - eye, m - eye) > reach * reach) continue;
                found =
                    sdRoundedCone(eye, {glm::vec3(a), radiusScale * a.w, glm::vec3(b), radiusScale * b.w}) <= radius;
            }
            return found;
        },
        [](bool x, bool y) { return x || y; });
}

RayInterval RaytracedRenderer::regionRayInterval(const Ray& ray) const {
    RayInterval iv = rayInterval(ray, m_region);
    if (iv.empty()) return iv;
    // Float slack for hit points on a box face, and room for the hit just before the face that a
    // joint duplicate is tested against (shadeTransparent): a few joint epsilons.
    auto pad = [&](float t) { return 4.0f * m_jointEpsilon + 1e-5f * std::abs(t); };
    return {iv.t0 - pad(iv.t0), iv.t1 + pad(iv.t1)};
}

bool RaytracedRenderer::tracedSpan(const Ray& ray, float& tnear, float& tfar) const {
    tnear = 0.0f;
    tfar = kInf;
    if (m_region.unbounded()) return true;
    const RayInterval iv = regionRayInterval(ray);
    if (iv.empty() || iv.t1 < 0.0f) return false;
    tnear = std::max(iv.t0, 0.0f);
    tfar = iv.t1;
    return true;
}

bool RaytracedRenderer::regionSurface(PixelContext& c, Surface& s) const {
    const RayInterval iv = regionRayInterval(c.ray);
    if (iv.empty() || iv.t1 < 0.0f) return false;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    float tnear = std::max(iv.t0, 0.0f);
    // Each pass starts behind the last hit, so the loop ends at the box's far side.
    for (;;) {
        RTCRayHit rh = makeRayHit(c.ray, tnear);
        rh.ray.tfar = iv.t1;
        rtcIntersect1(m_embree->scene(), &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
        ++c.hits;
        const FirstHit hit{true, rh.hit.primID, rh.ray.tfar, glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z)};
        bool anyCandidate = false;
        if (visibleSurface(c.ray, hit, true, s, anyCandidate)) return true;
        if (!anyCandidate && m_region.contains(c.ray.origin + hit.t * c.ray.dir)) {
            // Grazing, as shadeOpaque: Embree's hit, in this region by its own point.
            s = {hit.t, hit.prim, glm::dot(hit.ng, hit.ng) > 0.0f ? glm::normalize(hit.ng) : -c.ray.dir};
            return true;
        }
        tnear = std::nextafter(hit.t, kInf);
    }
}

void RaytracedRenderer::shadeSurface(PixelContext& c, const Surface& s) const {
    const StyledLines& L = m_lines;
    const float best = s.t;
    const std::uint32_t bestSeg = s.segment;
    const glm::vec3 bestN = s.normal;
    const glm::vec3 p = c.ray.origin + best * c.ray.dir;
    glm::vec3 base = m_color;
    if (!m_uniformColor) {
        // The colour at the point's projection onto the axis, between the two vertices' colours.
        const std::uint32_t v0 = L.segmentVertices[2 * bestSeg], v1 = L.segmentVertices[2 * bestSeg + 1];
        const glm::vec3 x0(L.positionRadius[v0]), x1(L.positionRadius[v1]);
        const glm::vec3 ba = x1 - x0;
        const float m0 = glm::dot(ba, ba);
        const float u = m0 > 0.0f ? glm::clamp(glm::dot(p - x0, ba) / m0, 0.0f, 1.0f) : 0.0f;
        base = glm::mix(glm::vec3(L.color[v0]), glm::vec3(L.color[v1]), u);
    }
    if (m_ao) {
        // As shaders/deferred_shading.frag: AO scales the albedo, at the normal facing the viewer.
        const glm::vec3 facing = glm::dot(bestN, c.ray.dir) <= 0.0f ? bestN : -bestN;
        c.ao = m_ao->visibility(p, facing, c.pixel, bestSeg);
        base *= c.ao;
    }
    const glm::vec3 rgb = shadeBlinnPhong(base, bestN, c.ray.dir, c.lightDir, m_lighting);
    c.rgba = glm::vec4(rgb, 1.0f);
    c.depth = best * c.depthScale;
    c.normal = bestN;
    // A cache miss per pixel on a dense set, so only for an id AOV that is written.
    if (m_aovs.id) c.id = m_segmentPolyline[bestSeg];
}

void RaytracedRenderer::shadeTransparent(PixelContext& c) const {
    const StyledLines& L = m_lines;
    HitCollector collector;
    rtcInitIntersectContext(&collector.context);
    collector.context.filter = collectHit;
    collector.capacity = m_hitsPerPass;

    glm::vec3 color(0.0f);
    float alpha = 0.0f;
    bool havePrev = false, first = true;
    RayHitRecord prev{};
    float tnear = 0.0f, tfar = kInf;
    const bool clips = !m_region.unbounded();
    if (!tracedSpan(c.ray, tnear, tfar)) return;
    for (;;) {
        const int n = collector.trace(m_embree->scene(), c.ray, tnear, tfar);
        bool done = false;
        for (int k = 0; k < n && !done; ++k) {
            const RayHitRecord& h = collector.hits[k];
            ++c.hits;
            if (!(h.t > 0.0f)) continue;
            const std::uint32_t v0 = L.segmentVertices[2 * h.prim], v1 = L.segmentVertices[2 * h.prim + 1];
            // A ray through the rim shared by adjacent segments at a joint is reported by both.
            // (Unjoined segments are separate rounded cones: both count, as without cap clipping.)
            const bool duplicate = m_joinNeighbours && havePrev && prev.back == h.back &&
                                   h.t - prev.t <= m_jointEpsilon &&
                                   (h.prim == prev.prim + 1 || prev.prim == h.prim + 1) &&
                                   m_segmentPolyline[h.prim] == m_segmentPolyline[prev.prim];
            havePrev = true;
            prev = h;
            if (duplicate) continue;
            const glm::vec4& a = L.positionRadius[v0];
            const glm::vec4& b = L.positionRadius[v1];
            if (h.back) {
                // Only the inner wall of a segment the eye is in counts (the references' rule).
                const float reach = glm::length(glm::vec3(b) - glm::vec3(a)) + a.w + b.w;
                if (h.t > 2.0f * reach) continue;
                if (!(sdRoundedCone(c.ray.origin, {glm::vec3(a), a.w, glm::vec3(b), b.w}) < 0.0f)) continue;
            }
            const glm::vec3 p = c.ray.origin + h.t * c.ray.dir;
            // Another region composites this entry (after the duplicate test, which every region
            // makes on the same hits, so a joint's pair counts once over all regions).
            if (clips && !m_region.contains(p)) continue;
            const glm::vec3 ba = glm::vec3(b) - glm::vec3(a);
            const float m0 = glm::dot(ba, ba);
            const float u = m0 > 0.0f ? glm::clamp(glm::dot(p - glm::vec3(a), ba) / m0, 0.0f, 1.0f) : 0.0f;
            glm::vec4 base = glm::mix(L.color[v0], L.color[v1], u);
            const float ngLen2 = glm::dot(h.ng, h.ng);
            const glm::vec3 nrm = ngLen2 > 0.0f ? h.ng / std::sqrt(ngLen2) : -c.ray.dir;
            if (m_ao) {
                // As shaders/transparent_fragment.glsl: per fragment, before shading.
                const glm::vec3 facing = glm::dot(nrm, c.ray.dir) <= 0.0f ? nrm : -nrm;
                base = glm::vec4(glm::vec3(base) * m_ao->visibility(p, facing, c.pixel, h.prim), base.w);
            }
            // Clamped like every transparent path (the GL k-buffer stores RGBA8).
            const glm::vec3 rgb =
                glm::clamp(shadeBlinnPhong(glm::vec3(base), nrm, c.ray.dir, c.lightDir, m_lighting), 0.0f, 1.0f);
            if (first) {
                first = false;
                c.depth = h.t * c.depthScale;
                c.normal = nrm;
                c.id = m_segmentPolyline[h.prim];
            }
            const float w = (1.0f - alpha) * base.w;
            color += w * rgb;
            alpha += w;
            if (m_alphaCutoff < 1.0f && alpha >= m_alphaCutoff) done = true;
        }
        if (done || n < collector.capacity) break;
        tnear = collector.continueBehindLast();
    }
    c.rgba = glm::vec4(color, alpha);
}

void RaytracedRenderer::shadeTransparentHalo(PixelContext& c, const FragmentView& view, bool originsInside) const {
    const StyledLines& L = m_lines;
    float tnear = 0.0f, tfar = kInf;
    const bool clips = !m_region.unbounded();
    if (!tracedSpan(c.ray, tnear, tfar)) return;
    // Where the traced part starts may lie inside grown cones: the eye's (originsInside), or a
    // region's box face, which cuts through rings whose segments own fragments in the box.
    const bool startsInside = originsInside || tnear > 0.0f;
    const glm::vec3 start = c.ray.origin + tnear * c.ray.dir;
    HitCollector collector;
    rtcInitIntersectContext(&collector.context);
    collector.context.filter = startsInside ? collectHit : collectEntry;
    collector.capacity = m_hitsPerPass;
    const HaloGeometry& ring = m_halo->geometry;
    // How far in front of the hit that names it a fragment can lie (the header), with room for
    // Embree's rounding of t; with rays that may start inside a grown cone, a late (exit) hit can
    // name a fragment at any t, so nothing is composited before the last hit.
    const float lookBack =
        startsInside ? kInf : 1.01f * (1.0f + ring.width) * L.maxRadius / std::max(c.depthScale, 1e-6f);

    struct Pending {
        SegmentFragment f;
        std::uint32_t segment;
    };
    // Not yet composited, and the fragments the last pass added; reused per thread (no allocation
    // per pixel once grown).
    thread_local std::vector<Pending> pending;
    pending.clear();
    std::size_t head = 0;
    auto before = [](const Pending& a, const Pending& b) {
        return a.f.depth < b.f.depth || (a.f.depth == b.f.depth && a.segment < b.segment);
    };

    glm::vec3 color(0.0f);
    float alpha = 0.0f;
    bool first = true, done = false;
    // Composites the pending fragments up to (excluding) sort parameter `frontier`, in order.
    auto compositeUpTo = [&](float frontier) {
        std::sort(pending.begin() + std::ptrdiff_t(head), pending.end(), before);
        for (; head < pending.size() && !done; ++head) {
            const Pending& p = pending[head];
            if (!(p.f.t < frontier)) break;
            const std::uint32_t v0 = L.segmentVertices[2 * p.segment], v1 = L.segmentVertices[2 * p.segment + 1];
            glm::vec4 base = glm::mix(L.color[v0], L.color[v1], p.f.along);
            glm::vec3 rgb;
            if (p.f.halo) {
                rgb = m_halo->color;  // the ring is not shaded
            } else {
                if (m_ao) {
                    const glm::vec3 pt = c.ray.origin + p.f.t * c.ray.dir;
                    const glm::vec3 facing = glm::dot(p.f.normal, c.ray.dir) <= 0.0f ? p.f.normal : -p.f.normal;
                    base = glm::vec4(glm::vec3(base) * m_ao->visibility(pt, facing, c.pixel, p.segment), base.w);
                }
                rgb = glm::clamp(shadeBlinnPhong(glm::vec3(base), p.f.normal, c.ray.dir, c.lightDir, m_lighting), 0.0f,
                                 1.0f);
            }
            if (first) {
                first = false;
                c.depth = p.f.depth;
                c.normal = p.f.normal;
                c.id = m_segmentPolyline[p.segment];
            }
            const float w = (1.0f - alpha) * base.w;
            color += w * rgb;
            alpha += w;
            if (m_alphaCutoff < 1.0f && alpha >= m_alphaCutoff) done = true;
        }
    };
    for (;;) {
        const int n = collector.trace(m_embree->scene(), c.ray, tnear, tfar);
        for (int k = 0; k < n; ++k) {
            const RayHitRecord& h = collector.hits[k];
            ++c.hits;
            // One hit per closed grown cone names its segment: the entry, or the exit of one the
            // traced part starts in.
            if (h.back) {
                if (!startsInside) continue;
                const glm::vec4& a = L.positionRadius[L.segmentVertices[2 * h.prim]];
                const glm::vec4& b = L.positionRadius[L.segmentVertices[2 * h.prim + 1]];
                if (!(sdRoundedCone(start, grownCone({glm::vec3(a), a.w, glm::vec3(b), b.w}, ring)) < 0.0f)) continue;
            }
            Pending p;
            p.segment = h.prim;
            if (!segmentFragmentOf(L, h.prim, c.ray, view, m_capClipping, &ring, p.f)) continue;
            // Another region composites a fragment whose surface point lies there (the GL rule:
            // the tube's entry, or the ring's).
            if (clips && !m_region.contains(c.ray.origin + p.f.tSurface * c.ray.dir)) continue;
            pending.push_back(p);
        }
        const bool last = n < collector.capacity;
        compositeUpTo(last ? kInf : collector.hits[n - 1].t - lookBack);
        if (done || last) break;
        tnear = collector.continueBehindLast();
    }
    c.rgba = glm::vec4(color, alpha);
}

nlohmann::json RaytracedRenderer::describe() const {
    nlohmann::json j = {{"technique", "raytraced"},
                        {"engine", "Embree " + std::to_string(RTC_VERSION_MAJOR) + "." +
                                       std::to_string(RTC_VERSION_MINOR) + "." + std::to_string(RTC_VERSION_PATCH)},
                        {"geometry", "RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE"},
                        {"neighbour_flags", m_joinNeighbours},
                        {"transparency", m_transparent ? "raytraced front-to-back" : "opaque"},
                        {"tile", kTile},
                        {"traversal", traversalName(m_traversal)},
                        {"threads", tbb::this_task_arena::max_concurrency()},
                        {"segments", m_lines.segmentCount()},
                        {"bvh_build_ms", m_embree->buildMs()},
                        {"bvh_memory_mb", double(m_embree->bytes()) / (1024.0 * 1024.0)},
                        {"bvh_peak_memory_mb", double(m_embree->peakBytes()) / (1024.0 * 1024.0)},
                        {"tile_cover_cells", m_cover.occupiedCells()},
                        {"ambient_occlusion", m_ao ? m_ao->describe() : nlohmann::json(false)}};
    if (!m_transparent) j["surface"] = m_exactSurface || !m_region.unbounded() ? "exact" : "embree";
    if (m_halo)
        j["halo"] = {{"width", m_halo->geometry.width},
                     {"depth", m_halo->geometry.depth},
                     {"geometry", "grown rounded cones, closed (no neighbour flags)"}};
    if (m_transparent) {
        j["alpha_cutoff"] = m_alphaCutoff;
        j["hits_per_pass"] = m_hitsPerPass;
        j["joint_epsilon"] = m_jointEpsilon;
    }
    return j;
}

}  // namespace tc::rt
