#pragma once
// A region of space for data-parallel rendering: one cell of a k-d decomposition
// (core/kd_decomposition.h). Regions tile space without overlap: each is half-open, [lo, hi) per
// axis, and the outermost faces are infinite. A tube or sphere contributes to the region that holds
// the point where the ray ENTERS it (the visible hit of an opaque frame, each front-facing entry
// of a transparent one), so every contribution to a pixel belongs to exactly one region and the
// regions' images composited in view order are the whole frame's.
#include <functional>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

#include "core/camera.h"
#include "core/line_set.h"

namespace tc {

struct RegionBox {
    glm::vec3 lo{-std::numeric_limits<float>::infinity()};
    glm::vec3 hi{std::numeric_limits<float>::infinity()};

    bool contains(const glm::vec3& p) const {
        return p.x >= lo.x && p.x < hi.x && p.y >= lo.y && p.y < hi.y && p.z >= lo.z && p.z < hi.z;
    }
    bool unbounded() const { return *this == RegionBox{}; }
    friend bool operator==(const RegionBox&, const RegionBox&) = default;

    // Whether the closed box [boxLo, boxHi] (a segment's or a sphere's bounds) can hold a point of
    // the region: boxLo < hi and boxHi >= lo on every axis. Geometry for which this is false has
    // no entry point in the region (every surface point lies in its bounds).
    bool reaches(const glm::vec3& boxLo, const glm::vec3& boxHi) const {
        return boxLo.x < hi.x && boxLo.y < hi.y && boxLo.z < hi.z && boxHi.x >= lo.x && boxHi.y >= lo.y &&
               boxHi.z >= lo.z;
    }
};

// The ray parameters [t0, t1] for which origin + t dir lies in the closed box [lo, hi] (slab test;
// t may be negative); empty() when the ray misses it. Infinite faces and rays parallel to a face
// are handled without NaN. The ray tracers restrict their rays to it (with a margin): the exact
// test is RegionBox::contains on each hit point.
struct RayInterval {
    float t0 = 0, t1 = 0;
    bool empty() const { return !(t0 <= t1); }
};
RayInterval rayInterval(const Ray& ray, const RegionBox& box);

// What a renderer needs to draw one region of a data-parallel frame: the box (TechniqueData::region),
// the bounds and largest radius of the whole dataset over all ranks (TechniqueData::bounds,
// ::maxRadius) and the density reduction of ambient occlusion (TechniqueHooks::reduceDensity).
// The default draws everything of its own data, as without data-parallel rendering.
struct RegionSetup {
    RegionBox box;
    // Every rank's data together; empty / 0 = the renderer's own data. The AO grid, the AO cone
    // length and the depth range derive from them, so every rank has the same grid and the same
    // depth buffer values as one process (whose depth test then breaks near-ties the same way).
    Bounds dataBounds;
    float dataMaxRadius = 0;
    // Replaces an AO density grid (finest level, x fastest) by the sum over all ranks'; null = none.
    std::function<void(std::vector<float>&)> reduceDensity;

    bool clips() const { return !box.unbounded(); }
    const Bounds& boundsOr(const Bounds& own) const { return dataBounds.empty() ? own : dataBounds; }
    float maxRadiusOr(float own) const { return dataMaxRadius > 0.0f ? dataMaxRadius : own; }
    // Which data this rank deposits into the AO density: with a reduction, only the segments whose
    // first vertex (the spheres whose centre) lies in the box. A rank receives every segment that
    // reaches its region, so a segment crossing a region face is held by several ranks; the owner
    // rule counts it once in the sum. Without a reduction, all of it (the density of this rank's
    // data alone).
    RegionBox densityOwner() const { return reduceDensity ? box : RegionBox{}; }
};

}  // namespace tc
