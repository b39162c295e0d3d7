#include "rt/primary_rays.h"

#include <algorithm>
#include <limits>

namespace tc::rt {

const char* traversalName(Traversal t) {
    switch (t) {
    case Traversal::Single: return "rtcIntersect1";
    case Traversal::Packet8: return "rtcIntersect8";
    case Traversal::Packet16: return "rtcIntersect16";
    case Traversal::Stream: return "rtcIntersect1M";
    }
    return "?";
}

namespace {

// The first hits of tile.rays[first .. first + count) as one rtcIntersectK packet (count <= K; the
// unused lanes are invalid).
template <int K, class RayHitK>
void tracePacket(RTCScene scene, RTCIntersectContext& context, const Tile& tile, int first, int count,
                 FirstHit* hits) {
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
    if constexpr (K == 8) rtcIntersect8(valid, scene, &context, &rh);
    else rtcIntersect16(valid, scene, &context, &rh);
    for (int j = 0; j < count; ++j) {
        FirstHit& h = hits[first + j];
        h.hit = rh.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID;
        h.prim = rh.hit.primID[j];
        h.t = rh.ray.tfar[j];
        h.ng = glm::vec3(rh.hit.Ng_x[j], rh.hit.Ng_y[j], rh.hit.Ng_z[j]);
    }
}

}  // namespace

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
