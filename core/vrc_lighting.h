#pragma once
// Lighting of voxel-based line ray casting on the Eq. 1 density of the voxel model (Kanzler,
// Rautenhaus & Westermann 2019, Sec. 5.3; core/vrc_model.h, LoD): the CPU twin of the density
// rays of shaders/vrc_lighting.glsl, used to check the GPU's per-voxel precomputed AO.
//
// Density rays (Sec. 5.3, first approach). From a point, a ray samples the level-0 density by
// trilinear interpolation (texel centres at voxel centres, zero outside the grid) at distances
// 1, 2, ..., radius voxels (one voxel steps, Sec. 6.4) and adds the samples, each standing for
// one voxel of path: the ray's occlusion is min(1, sum) ("accumulated until either full blocking
// is reached (line density 1) or the ray reaches beyond the radius of influence or leaves the
// domain"). Sampling stops at the first sample outside the grid box.
//
// Spherical AO (Sec. 5.3, second approach; Sec. 6.4: 100 rays): 1 - the mean occlusion of `rays`
// directions spread evenly over the whole sphere (a Fibonacci sphere), independent of the surface
// orientation.
#include <glm/glm.hpp>
#include <vector>

#include "core/vrc_model.h"

namespace tc {

// Trilinear read of `level` at `p` in the level's voxel coordinates (voxel i spans [i, i + 1)).
float sampleVrcDensity(const VrcDensityLevel& level, glm::vec3 p);

// `n` unit directions evenly over the sphere: z = 1 - 2 (i + 0.5) / n, azimuth i x the golden
// angle (the same set as vrcSphereDirection in shaders/vrc_lighting.glsl).
glm::vec3 vrcSphereDirection(int i, int n);

// Occlusion in [0, 1] of one density ray from `p` (level-0 voxel coordinates) along unit `dir`.
float vrcDensityRayOcclusion(const VrcDensityLevel& level0, glm::vec3 p, glm::vec3 dir, float radiusVoxels);

// 1 - mean occlusion of `rays` density rays over the sphere around `p`.
float vrcSphereAmbientOcclusion(const VrcDensityLevel& level0, glm::vec3 p, int rays, float radiusVoxels);

}  // namespace tc
