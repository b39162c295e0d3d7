#include "rt/primary_rays.h"

#include <algorithm>
#include <limits>

namespace tc::rt {

const char* traversalName(Traversal t) {
    switch (t) {
        case Traversal::Single:
            return "rtcIntersect1";
        case Traversal::Packet8:
            return "rtcIntersect8";
        case Traversal::Packet16:
            return "rtcIntersect16";
        case Traversal::Stream:
            return "rtcIntersect1M";
    }
    return "?";
}

namespace {

// The first hits of tile.rays[first .. first + count) as one rtcIntersectK packet (count <= K; the
// unused lanes are invalid).
template <int K, class RayHitK>
void tracePacket(RTCScene scene, RTCIntersectContext& context, const Tile& tile, int first, int count, FirstHit* hits) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    alignas(64) int valid[K];
    alignas(64) RayHitK rh;
    for (int j = 0; j < K; ++j) {
        const bool inside = j < count;
        valid[j] = inside ? -1 : 0;
        const Ray& r = tile.rays[first + (inside ? j : 0)];
        rh.ray.org_x[j] = r.origin.x;
        rh.ray.org_y[j] = r.origin.y;
        rh.ray.org_z[j] = r.origin.z;
        rh.ray.dir_x[j] = r.dir.x;
        rh.ray.dir_y[j] = r.dir.y;
        rh.ray.dir_z[j] = r.dir.z;
        rh.ray.tnear[j] = 0.0f;
        rh.ray.tfar[j] = kInf;
        rh.ray.time[j] = 0.0f;
        rh.ray.mask[j] = 0xFFFFFFFFu;
        rh.ray.id[j] = unsigned(j);
        rh.ray.flags[j] = 0;
        rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID[j] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
    }
    if constexpr (K == 8)
        rtcIntersect8(valid, scene, &context, &rh);
    else
        rtcIntersect16(valid, scene, &context, &rh);
    for (int j = 0; j < count; ++j) {
        FirstHit& h = hits[first + j];
        h.hit = rh.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID;
        h.prim = rh.hit.primID[j];
        h.t = rh.ray.tfar[j];
        h.ng = glm::vec3(rh.hit.Ng_x[j], rh.hit.Ng_y[j], rh.hit.Ng_z[j]);
    }
}

}  // namespace

SceneBounds sceneBounds(RTCScene scene) {
    alignas(16) RTCBounds b;
    rtcGetSceneBounds(scene, &b);
    SceneBounds box{{b.lower_x, b.lower_y, b.lower_z}, {b.upper_x, b.upper_y, b.upper_z}};
    // Grown by a little of its size: Embree's bounds are tight, the test below is in floats.
    const glm::vec3 pad = 1e-4f * (box.hi - box.lo) + 1e-6f * glm::max(glm::abs(box.lo), glm::abs(box.hi)) + 1e-30f;
    box.lo -= pad;
    box.hi += pad;
    return box;
}

bool pixelBlockMisses(const PixelRays& rays, const ImageWindow& window, int x0, int y0, int w, int h,
                      const SceneBounds& box) {
    if (!(box.lo.x <= box.hi.x && box.lo.y <= box.hi.y && box.lo.z <= box.hi.z)) return true;  // empty scene
    // PixelRays(px, py) passes through the centre of pixel (px, py), i.e. continuous position
    // (px + 0.5, py + 0.5); the block with one pixel of margin spans px in [x0 - 1.5, x0 + w + 0.5].
    const float left = float(x0) - 1.5f, right = float(x0 + w) + 0.5f;
    const float top = float(y0) - 1.5f, bottom = float(y0 + h) + 0.5f;
    auto ray = [&](float px, float py) {
        const glm::vec2 p = fullImagePixel(window, px, py);
        return rays(p.x, p.y);
    };
    const Ray corner[4] = {ray(left, top), ray(right, top), ray(right, bottom), ray(left, bottom)};
    const Ray centre = ray(0.5f * (left + right), 0.5f * (top + bottom));
    const glm::vec3 inside = centre.origin + centre.dir;
    for (int i = 0; i < 4; ++i) {
        const Ray& a = corner[i];
        const Ray& b = corner[(i + 1) % 4];
        // The side through ray a and ray b: it holds a's origin and direction and a point of b
        // (perspective: both start at the eye; orthographic: parallel rays, other origins).
        glm::vec3 n = glm::cross(a.dir, b.origin + b.dir - a.origin);
        if (glm::dot(n, inside - a.origin) < 0.0f) n = -n;
        // The box corner farthest along n: if even it is outside, the whole box is.
        const glm::vec3 far(n.x > 0.0f ? box.hi.x : box.lo.x, n.y > 0.0f ? box.hi.y : box.lo.y,
                            n.z > 0.0f ? box.hi.z : box.lo.z);
        const float slack = 1e-5f * glm::length(n) * (glm::length(far - a.origin) + 1.0f);
        if (glm::dot(n, far - a.origin) < -slack) return true;
    }
    return false;
}

void traceFirstHits(RTCScene scene, Traversal traversal, const Tile& tile, FirstHit* hits) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    const int n = tile.count();
    auto setRay = [](RTCRayHit& rh, const Ray& r) { rh = makeRayHit(r, 0.0f); };
    auto record = [](FirstHit& h, const RTCRayHit& rh) {
        h.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        h.prim = rh.hit.primID;
        h.t = rh.ray.tfar;
        h.ng = glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    };
    switch (traversal) {
        case Traversal::Single:
            for (int k = 0; k < n; ++k) {
                RTCRayHit rh;
                setRay(rh, tile.rays[k]);
                rtcIntersect1(scene, &context, &rh);
                record(hits[k], rh);
            }
            break;
        case Traversal::Packet8:
            // One tile row per packet: adjacent pixels, so the packet's rays share most BVH nodes.
            static_assert(kTile == 8, "one rtcIntersect8 packet per tile row");
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            for (int row = 0; row < tile.h; ++row)
                tracePacket<8, RTCRayHit8>(scene, context, tile, row * tile.w, std::min(8, n - row * tile.w), hits);
            break;
        case Traversal::Packet16:
            // Two tile rows per packet (8x2 pixels; a partial tile row packs its rows contiguously).
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            for (int first = 0; first < n; first += 16)
                tracePacket<16, RTCRayHit16>(scene, context, tile, first, std::min(16, n - first), hits);
            break;
        case Traversal::Stream: {
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            RTCRayHit rh[kTile * kTile];
            for (int k = 0; k < n; ++k) setRay(rh[k], tile.rays[k]);
            rtcIntersect1M(scene, &context, rh, unsigned(n), sizeof(RTCRayHit));
            for (int k = 0; k < n; ++k) record(hits[k], rh[k]);
            break;
        }
    }
}

}  // namespace tc::rt
