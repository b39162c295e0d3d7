#pragma once
// The K nearest hits of one ray, gathered by an Embree context filter (RTCIntersectContext::
// filter) for front-to-back compositing in exact order. Shared by the tubes
// (rt/raytraced_renderer.cpp) and the particles (rt/raytraced_particles.cpp), whose filters differ
// only in which hits count and at which key they sort.
//
// Embree calls the context filter for every candidate hit with ray.tfar set to the hit's t. The
// collector keeps the `capacity` nearest hits strictly after `last` (the hits composited by
// earlier passes); when it is full it accepts only a hit that became the farthest kept one, so
// Embree's tfar shrinks to the K-th nearest and traversal prunes everything behind it. Every other
// hit is rejected (valid = 0), which makes Embree continue as if it had missed. A pixel that needs
// more than K hits traces again from just before the K-th (the filter skips it and everything
// before by `last`).
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>

#include "rt/primary_rays.h"

namespace tc::rt {

constexpr int kMaxHitsPerPass = 48;

// Hits gathered per traversal: cut-off rays usually stop within the first pass; exact ones
// (alpha cutoff 1) take fewer passes with a larger K.
inline int hitsPerPass(float alphaCutoff) {
    return alphaCutoff >= 1.0f ? kMaxHitsPerPass : 16;
}

// Hits gathered per traversal of a transparent tube ray whose surfaces have about `opacity`. A
// tube ray enters and leaves every tube, so n front-facing layers are about 2n hits, n the layers
// of `opacity` that reach the cutoff: 1 - (1 - opacity)^n >= cutoff. A pass costs more the larger
// K is (the traversal cannot prune behind the K-th nearest hit before it has K), and a second pass
// costs about as much as the first, so K just above the need, 2n + 2, is fastest where many layers
// are needed; where few are, one hit per traversal (K = 1, each pass pruned from its first hit) is.
// Measured on the 1M spiral set (docs/performance.md, "Ray tracing on the CPU", hit batching):
// opacity 0.3 (13 layers, ~24 hits per covered pixel): K = 28 2.5x faster than K = 1; opacity
// 0.6 (6 layers): K = 14 11 % faster; opacity 0.8 (3 layers): K = 1 2x faster than K = 8.
constexpr int kMinLayersToBatch = 5;
inline int hitsPerPass(float alphaCutoff, float opacity) {
    if (alphaCutoff >= 1.0f) return kMaxHitsPerPass;
    const float a = std::clamp(opacity, 0.01f, 0.99f);
    const float layers = std::ceil(std::log(1.0f - alphaCutoff) / std::log(1.0f - a));
    if (layers < float(kMinLayersToBatch)) return 1;
    return int(std::min(2.0f * layers + 2.0f, float(kMaxHitsPerPass)));
}

struct RayHitRecord {
    float t;  // sort key along the ray (<= the hit's Embree t)
    std::uint32_t prim;
    std::uint32_t back;  // 1 = back-facing (leaving a surface)
    glm::vec3 ng;        // unnormalised geometric normal from Embree (outward)
};

// Total order of hits along a ray: by t, then primitive, then front before back, so hits at equal
// t are composited deterministically (as the references sort by (depth, primitive)).
inline bool hitLess(const RayHitRecord& a, const RayHitRecord& b) {
    if (a.t != b.t) return a.t < b.t;
    if (a.prim != b.prim) return a.prim < b.prim;
    return a.back < b.back;
}

// The candidate hit a context filter is called with: t = the ray's tfar, primitive, Embree's
// geometric normal and whether it faces away from the ray; callers change t (the sort key) as
// their filter needs.
inline RayHitRecord hitRecordOf(const RTCFilterFunctionNArguments* args) {
    const RTCRay* ray = reinterpret_cast<const RTCRay*>(args->ray);
    const RTCHit* hit = reinterpret_cast<const RTCHit*>(args->hit);
    RayHitRecord h;
    h.t = ray->tfar;
    h.prim = hit->primID;
    h.ng = glm::vec3(hit->Ng_x, hit->Ng_y, hit->Ng_z);
    h.back = glm::dot(h.ng, glm::vec3(ray->dir_x, ray->dir_y, ray->dir_z)) > 0.0f ? 1u : 0u;
    return h;
}

struct HitCollector {
    RTCIntersectContext context;  // first member: Embree hands back a pointer to it
    RayHitRecord hits[kMaxHitsPerPass];
    int capacity = 0;
    int count = 0;
    bool haveLast = false;
    RayHitRecord last{};
    const void* user = nullptr;  // the filter's own data (the particle renderer)

    static HitCollector& of(const RTCFilterFunctionNArguments* args) {
        return *reinterpret_cast<HitCollector*>(const_cast<RTCIntersectContext*>(args->context));
    }

    // Inserts `h` if it is among the K nearest after `last`; returns whether Embree should accept
    // the hit (only when the list is full and h is its farthest).
    bool offer(const RayHitRecord& h) {
        if (haveLast && !hitLess(last, h)) return false;
        if (count == capacity) {
            if (!hitLess(h, hits[count - 1])) return false;
            --count;  // drop the farthest
        }
        int i = count++;
        while (i > 0 && hitLess(h, hits[i - 1])) {
            hits[i] = hits[i - 1];
            --i;
        }
        hits[i] = h;
        return count == capacity && i == count - 1;
    }

    // One pass: traverses `scene` along `ray` over [tnear, tfar] with this list's filter, the list
    // emptied first; returns how many hits it kept (sorted in hits[0, count)).
    int trace(RTCScene scene, const Ray& ray, float tnear, float tfar) {
        count = 0;
        RTCRayHit rh = makeRayHit(ray, tnear);
        rh.ray.tfar = tfar;
        rtcIntersect1(scene, &context, &rh);
        return count;
    }

    // Prepares the next pass behind the farthest hit of this one; returns its tnear.
    float continueBehindLast() {
        haveLast = true;
        last = hits[count - 1];
        count = 0;
        float tnear = std::nextafter(last.t, -std::numeric_limits<float>::infinity());
        return tnear >= 0.0f ? tnear : 0.0f;
    }
};

}  // namespace tc::rt
