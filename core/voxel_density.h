#pragma once
// The density volume behind line ambient occlusion (Groß & Gumhold 2020, Sect. 5.3): how much of
// each voxel the tubes fill, weighted by their opacity. Built on the CPU with oneTBB; the GL side
// uploads `density` as a single-channel float 3D texture and builds its mip pyramid.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/line_set.h"
#include "core/region.h"
#include "core/styled_lines.h"

namespace tc {

// A regular grid of cubic voxels. Voxel (x, y, z) covers
// [origin + (x, y, z) * voxelSize, origin + (x + 1, y + 1, z + 1) * voxelSize).
// density is in units of "voxel volumes of fully opaque tube": 1 means the voxel is filled once
// by tubes of opacity 1 (overlapping tubes add, so values above 1 occur).
struct DensityGrid {
    glm::ivec3 size{0};
    glm::vec3 origin{0.0f};
    float voxelSize = 0.0f;
    std::vector<float> density;       // size.x * size.y * size.z, x fastest
    std::size_t clampedSegments = 0;  // segments whose axis lies (partly) outside the grid

    std::size_t voxelCount() const { return std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z); }
    std::size_t index(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(size.y) + std::size_t(y)) * std::size_t(size.x) + std::size_t(x);
    }
    glm::vec3 hi() const { return origin + glm::vec3(size) * voxelSize; }

    // Sum of all voxels (in double, in index order).
    double total() const;
    // Trilinear interpolation between voxel centres, as a GL_LINEAR 3D texture with a zero
    // border would return it: outside the grid the density is 0.
    float sample(const glm::vec3& worldPos) const;

    // Bytes of `density` (what the 3D texture's level 0 takes).
    std::size_t bytes() const { return voxelCount() * sizeof(float); }
    // Bytes of the transient 64-bit fixed-point accumulator voxelizeLines allocates on top: one
    // int64 per voxel, in bricks of 8^3 (each axis rounded up to a multiple of 8).
    std::size_t accumulatorBytes() const {
        const glm::ivec3 padded = (size + 7) / 8 * 8;
        return std::size_t(padded.x) * std::size_t(padded.y) * std::size_t(padded.z) * sizeof(std::int64_t);
    }
};

// Fixed-point scale of the accumulator: 2^32 per unit of density. A deposit is rounded to the
// nearest 2^-32 (2.3e-10 voxel volumes); one voxel holds up to 2^31 (2.1e9) voxel volumes
// (int64 range / scale), i.e. 2^31 fully opaque tubes through it; overflow is checked.
inline constexpr double kDensityFixedPointScale = 4294967296.0;

// A zeroed grid of cubic voxels with `resolution` (>= 2) voxels along the longest extent of
// `bounds` and the other axes fitted (rounded up), centred on the bounds. The voxel size is
// longest extent / (resolution - 1): the grid is half a voxel larger than the bounds on every
// side along the longest axis (and at least that along the others), so a tube axis on a face of
// the bounds lies strictly inside the grid instead of on its outer face, where float rounding
// would decide whether it is voxelized or clamped. Degenerate (flat or point) bounds get a voxel
// size from the longest non-zero extent, or 1 when all are zero. Checks that bounds is not empty.
DensityGrid makeDensityGrid(const Bounds& bounds, int resolution);

// Replaces grid.density with the opacity-weighted tube volume per voxel, and sets
// grid.clampedSegments. For every segment, the voxels its axis passes are traversed with
// Amanatides & Woo's 3D DDA; the piece of the axis inside a voxel, with the radius r(s) and the
// opacity a(s) (vertex alpha) both interpolated linearly along the segment, deposits
//     pi * L * integral over the piece of r(s)^2 a(s) ds / voxelSize^3
// into that voxel (L the segment length, s in [0,1]): for constant opacity the truncated cone's
// volume pi l (ra^2 + ra rb + rb^2) / 3. The whole cross-section goes to the voxel holding the
// axis (the paper's approximation). The spherical caps of the rounded cones are not added: a cap
// is shared by the two segments meeting at a vertex and mostly lies inside its neighbour's cone,
// so adding them would count every joint about twice; only the two end caps of a polyline are
// lost (2/3 pi r^3 each, small against the tube for r << segment length).
// Parts of an axis outside the grid are not deposited; such segments count in clampedSegments.
// A point exactly on a voxel face belongs to the voxel with the larger index (floor), so axes on
// faces or edges deposit into one deterministic row of voxels.
// Runs tbb::parallel_for over segments and accumulates in 64-bit fixed point (see
// kDensityFixedPointScale) with atomic adds into 8^3-voxel bricks: integer addition is
// associative, so the result is bit-identical for any thread count, schedule or segment order. Peak
// memory: grid.bytes() + grid.accumulatorBytes().
// `owner`: only the segments whose first vertex lies in it deposit (RegionSetup::densityOwner,
// data-parallel rendering); the default box holds every finite point.
void voxelizeLines(const StyledLines& lines, DensityGrid& grid, const RegionBox& owner = {});

// The density grid of line AO as the renderers build it: makeDensityGrid over
// region.boundsOr(lines.bounds) at `resolution`, voxelizeLines with region.densityOwner(), then
// region.reduceDensity (when set) replaces the densities by the sum over all ranks, so a rank
// holding part of the data sees the density of all of it. clampedSegments counts this rank's.
DensityGrid buildLineDensity(const StyledLines& lines, int resolution, const RegionSetup& region);

// Amanatides & Woo traversal of a line a + s d in grid coordinates (voxel v covers [v, v + 1)),
// shared by the density voxelization and the VRC model (core/vrc_model.cpp).
struct VoxelWalk {
    glm::dvec3 a, invD;
    glm::ivec3 step;

    VoxelWalk(const glm::dvec3& a, const glm::dvec3& d) : a(a) {
        for (int k = 0; k < 3; ++k) {
            step[k] = d[k] > 0.0 ? 1 : (d[k] < 0.0 ? -1 : 0);
            invD[k] = d[k] != 0.0 ? 1.0 / d[k] : 0.0;
        }
    }

    // The first face of voxel v the line crosses after parameter `s`, if before `sEnd`: returns
    // its parameter (>= s) and sets `axis`; otherwise returns max(sEnd, s) with axis = -1. Each
    // face's parameter comes from the face's coordinate rather than an accumulated one, so it
    // does not drift; ties (an edge or corner) step x before y before z, so a line through an
    // edge visits a fixed neighbour with a zero-length piece.
    double nextFace(const glm::ivec3& v, double s, double sEnd, int& axis) const {
        double sNext = sEnd;
        axis = -1;
        for (int k = 0; k < 3; ++k) {
            if (step[k] == 0) continue;
            const double face = step[k] > 0 ? v[k] + 1 : v[k];
            const double sk = (face - a[k]) * invD[k];
            if (sk < sNext) {
                sNext = sk;
                axis = k;
            }
        }
        return std::max(sNext, s);
    }
};

}  // namespace tc
