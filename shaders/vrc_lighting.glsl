// Lighting of voxel-based line ray casting as Kanzler, Rautenhaus & Westermann 2019 compute it
// (Sec. 5.2, 5.3), on the Eq. 1 density pyramid of the voxel model (core/vrc_model.h, LoD: per
// voxel the lines' length x opacity in voxel lengths, coarser levels averaging 2x2x2 blocks).
// gl/vrc_renderer.cpp sets the uniforms; the includer declares uGridOrigin, uVoxelSize, uGridSize
// (the model grid). Positions below are level-0 voxel coordinates pv = (p - uGridOrigin) / uVoxelSize.
//
// Defines:
//   VRC_DENSITY_AO         AO from `uVrcAoRays` density rays over the hemisphere around the normal
//                          (Sec. 5.3, first approach; core/vrc_lighting.h is the CPU twin);
//   VRC_PRECOMPUTED_AO     AO from the per-voxel spherical AO of shaders/vrc_ao_precompute.comp
//                          (Sec. 5.3, second approach), read trilinearly at the hit;
//   VRC_DENSITY_SHADOWS    soft shadows: one cone toward the light through the pyramid whose
//                          aperture subtends one voxel at the finest level (Sec. 5.2);
//   VRC_HARD_TUBE_SHADOWS  hard shadows: one ray toward the light against the tubes of the voxel
//                          model's pieces (Sec. 5.2, Fig. 12a/b; needs the ray caster's piece access,
//                          so only vrc_raycast.comp defines it).
//
// Own tube. A point on a tube lies in the density its own line deposits: a density ray leaving
// it reads its own line for the first ~2 voxels (and all along a grazing ray), so an isolated tube
// would occlude itself. As shaders/cone_tracing.glsl ("Self-occlusion"), reads that can reach the
// shaded piece's axis (as an infinite line) filter by hand and take from every texel what the line
// leaves in it: opacity x the line's length inside the texel's box / texel volume, which is what
// Eq. 1 deposits for a straight line. The paper does not say how it treats the own line.

#include "cone_tracing.glsl"

#if defined(VRC_DENSITY_AO) || defined(VRC_PRECOMPUTED_AO) || defined(VRC_DENSITY_SHADOWS) || defined(VRC_AO_PRECOMPUTE)
#define VRC_EQ1_DENSITY
// The pyramid as one R16F 3D texture whose mip l is level l (level 0 padded with zero voxels to
// uVrcDensityTexSize, a multiple of 2^uVrcDensityMaxLevel, so every mip halves evenly and a texel
// of level l spans 2^l voxels exactly). Clamped to a zero border: outside the grid is empty.
uniform sampler3D uVrcDensity;
uniform vec3 uVrcDensityTexSize;
uniform int uVrcDensityMaxLevel;
uniform float uVrcAoRadius;  // radius of influence of the density rays, voxels (Sec. 5.3: 15)
uniform float uVrcAoStrength;
#endif
#ifdef VRC_DENSITY_AO
uniform int uVrcAoRays;
#endif
#ifdef VRC_PRECOMPUTED_AO
uniform sampler3D uVrcAoVolume;  // per-voxel spherical AO at voxel centres, the model grid's size
#endif

// The shaded piece's axis as an infinite line (voxel coordinates, unit direction) and its opacity.
struct VrcOwnLine {
    vec3 origin;
    vec3 dir;
    float alpha;
};

VrcOwnLine vrcOwnLine(vec4 end0, vec4 end1, float alpha) {
    vec3 a = (end0.xyz - uGridOrigin) / uVoxelSize, b = (end1.xyz - uGridOrigin) / uVoxelSize;
    vec3 d = b - a;
    float len2 = dot(d, d);
    return VrcOwnLine(a, len2 > 0.0 ? d * inversesqrt(len2) : vec3(0.0, 0.0, 1.0), len2 > 0.0 ? alpha : 0.0);
}

vec3 vrcVoxelCoords(vec3 p) { return (p - uGridOrigin) / uVoxelSize; }

// Direction i of n evenly over the sphere (twin of tc::vrcSphereDirection).
vec3 vrcSphereDirection(int i, int n) {
    float z = 1.0 - 2.0 * (float(i) + 0.5) / float(n);
    float s = sqrt(max(0.0, 1.0 - z * z));
    float phi = float(i) * 2.39996323;
    return vec3(s * cos(phi), s * sin(phi), z);
}

#ifdef VRC_EQ1_DENSITY
// Mean Eq. 1 density around pv over a box of about 2^lod voxels (quadrilinear).
float vrcDensity(vec3 pv, float lod) { return textureLod(uVrcDensity, pv / uVrcDensityTexSize, lod).r; }

// One level's trilinear read at pv, each texel less the own line's deposit in it (clamped at 0).
float vrcLevelDensityExcluding(vec3 pv, int level, VrcOwnLine own) {
    float w = float(1 << level);
    ivec3 n = ivec3(uVrcDensityTexSize) >> level;
    vec3 c = pv / w - 0.5;
    vec3 base = floor(c);
    vec3 f = c - base;
    ivec3 i0 = ivec3(base);
    vec3 invU = vec3(own.dir.x != 0.0 ? 1.0 / own.dir.x : 1e30, own.dir.y != 0.0 ? 1.0 / own.dir.y : 1e30,
                     own.dir.z != 0.0 ? 1.0 / own.dir.z : 1e30);
    // Texel boxes grown by kConeOwnSlack voxels (cone_tracing.glsl: an axis on a voxel face), the
    // deposit by kConeOwnMargin (rounding of the pyramid's sums and of R16F).
    float perLength = 1.002 * kConeOwnMargin * own.alpha / (w * w * w);
    float sum = 0.0;
    for (int k = 0; k < 8; ++k) {
        ivec3 d = ivec3(k & 1, (k >> 1) & 1, k >> 2);
        ivec3 i = i0 + d;
        if (any(lessThan(i, ivec3(0))) || any(greaterThanEqual(i, n))) continue;
        vec3 lo = vec3(i) * w - kConeOwnSlack, hi = vec3(i + 1) * w + kConeOwnSlack;
        vec3 ta = (lo - own.origin) * invU, tb = (hi - own.origin) * invU;
        vec3 tNear = min(ta, tb), tFar = max(ta, tb);
        float len = max(min(min(tFar.x, tFar.y), tFar.z) - max(max(tNear.x, tNear.y), tNear.z), 0.0);
        vec3 w3 = mix(1.0 - f, f, vec3(d));
        sum += w3.x * w3.y * w3.z * max(texelFetch(uVrcDensity, i, level).r - perLength * len, 0.0);
    }
    return sum;
}

// vrcDensity without the own line where the read can reach it: the 2x2x2 texels of level
// ceil(lod) around pv span pv +- 1.5 texels per axis.
float vrcDensityNear(vec3 pv, float lod, VrcOwnLine own) {
    float level = clamp(lod, 0.0, float(uVrcDensityMaxLevel));
    vec3 d = pv - own.origin;
    float along = dot(d, own.dir);
    float reach = 2.6 * exp2(ceil(level)) + 2.0 * kConeOwnSlack;  // 1.5 sqrt(3) texels
    if (own.alpha <= 0.0 || dot(d, d) - along * along > reach * reach) return vrcDensity(pv, level);
    int l0 = int(floor(level));
    float fl = level - float(l0);
    float a = vrcLevelDensityExcluding(pv, l0, own);
    if (fl > 0.0) a = mix(a, vrcLevelDensityExcluding(pv, l0 + 1, own), fl);
    return a;
}

// Occlusion of one density ray from pv along unit dir (core/vrc_lighting.h): level-0 samples one
// voxel apart from 1 to uVrcAoRadius voxels, summed until full blocking (1) or the ray leaves the
// grid.
float vrcDensityRayOcclusion(vec3 pv, vec3 dir, VrcOwnLine own) {
    float sum = 0.0;
    vec3 hi = vec3(uGridSize);
    for (int k = 1; float(k) <= uVrcAoRadius; ++k) {
        vec3 q = pv + float(k) * dir;
        if (any(lessThan(q, vec3(0.0))) || any(greaterThan(q, hi))) break;
        sum += vrcDensityNear(q, 0.0, own);
        if (sum >= 1.0) return 1.0;
    }
    return sum;
}
#endif

#ifdef VRC_DENSITY_AO
// 1 - strength x mean occlusion of uVrcAoRays rays evenly over the hemisphere around n (uniform
// in solid angle, each ray weighted equally, as the paper's "normalized by dividing through the
// number of rays"). The set is the upper half of a Fibonacci sphere turned so that its azimuth 0
// is the own axis projected onto the tangent plane (continuous as the normal turns around the
// tube; cone_tracing.glsl's frame of n where that projection vanishes).
float vrcDensityRayAmbientOcclusion(vec3 pos, vec3 n, VrcOwnLine own) {
    vec3 t, b;
    vec3 axis = own.dir - dot(own.dir, n) * n;
    if (own.alpha > 0.0 && dot(axis, axis) > 0.07) {  // beyond ~15 degrees of the axis
        t = normalize(axis);
        b = cross(n, t);
    } else {
        coneTangentFrame(n, t, b);
    }
    vec3 pv = vrcVoxelCoords(pos);
    float occlusion = 0.0;
    for (int i = 0; i < uVrcAoRays; ++i) {
        // Upper half of a sphere of 2 x rays directions: z = 1 - (i + 0.5) / rays.
        vec3 s = vrcSphereDirection(i, 2 * uVrcAoRays);
        occlusion += vrcDensityRayOcclusion(pv, s.x * t + s.y * b + s.z * n, own);
    }
    return clamp(1.0 - uVrcAoStrength * occlusion / float(uVrcAoRays), 0.0, 1.0);
}
#endif

#ifdef VRC_PRECOMPUTED_AO
// The precomputed spherical AO, trilinear between voxel centres, scaled by the strength.
float vrcPrecomputedAmbientOcclusion(vec3 pos) {
    float ao = texture(uVrcAoVolume, vrcVoxelCoords(pos) / vec3(uGridSize)).r;
    return clamp(1.0 - uVrcAoStrength * (1.0 - ao), 0.0, 1.0);
}
#endif

#ifdef VRC_DENSITY_SHADOWS
// Occlusion toward the light (unit dir) through the pyramid, as cone tracing (Crassin et al.
// 2011, the paper's [4]): the cone's diameter at distance t is t voxels, so its aperture subtends
// one voxel at one voxel's distance (2 atan(1/2), 53 degrees) and the read at t is at level
// log2(t), "ever coarser resolution levels with increasing distance". Steps of half a diameter
// from t = 1 voxel to the grid's exit; a step of length s through mean density rho blocks
// min(1, rho s) (Eq. 1's length x opacity per voxel read as opacity per voxel of path, as the AO
// rays), composited front to back.
float vrcDensityConeOcclusion(vec3 pos, vec3 dir, VrcOwnLine own) {
    vec3 pv = vrcVoxelCoords(pos);
    vec3 inv = vec3(dir.x != 0.0 ? 1.0 / dir.x : 1e30, dir.y != 0.0 ? 1.0 / dir.y : 1e30,
                    dir.z != 0.0 ? 1.0 / dir.z : 1e30);
    vec3 ta = -pv * inv, tb = (vec3(uGridSize) - pv) * inv;
    float tEnd = min(min(max(ta.x, tb.x), max(ta.y, tb.y)), max(ta.z, tb.z));
    float occlusion = 0.0;
    float t = 1.0;
    for (int i = 0; i < 64 && t < tEnd && occlusion < 0.99; ++i) {
        float step = max(0.5 * t, 1.0);
        float rho = vrcDensityNear(pv + t * dir, log2(t), own);
        occlusion += (1.0 - occlusion) * min(rho * step, 1.0);
        t += step;
    }
    return occlusion;
}
#endif

#ifdef VRC_HARD_TUBE_SHADOWS
// The ray meets a tube of the pieces of voxel v inside [tEnter, tExit] (the voxel's part of the
// ray: with copies a voxel's pieces are all the tubes with surface in it, so every tube the ray
// meets is found in the voxel where it meets it).
bool vrcShadowRayHitsVoxel(Ray ray, ivec3 v, float tEnter, float tExit) {
    if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, uGridSize))) return false;
    uvec2 h = vrcHeaderAt((v.z * uGridSize.y + v.y) * uGridSize.x + v.x);
    uint count = h.y & kVrcCountMask;
    for (uint k = 0u; k < count; ++k) {
        VrcPiece p = vrcPiece(h.x + k, v);
        float rMax = max(p.cone.r0, p.cone.r1) * 1.0001 + 1e-4 * uVoxelSize;
        if (raySegmentDistance2(ray, tEnter, tExit, p.cone.x0, p.cone.x1) > rMax * rMax) continue;
        ConeInterval iv = intersectRoundedCone(ray, p.cone);
        if (iv.hit && max(iv.tIn, tEnter) <= min(iv.tOut, tExit)) return true;
    }
    return false;
}

// 0 when the ray from pos (moved 1e-3 voxel off the surface along its outward normal n) toward the
// light meets any tube of the voxel model, else 1: a 3D DDA over the model grid as the primary
// rays, the pieces of each voxel (with NEIGHBORS those of its 3x3x3 block) tested on the voxel's
// ray interval, stopping at the first hit.
float vrcHardTubeVisibility(vec3 pos, vec3 n) {
    Ray ray;
    ray.origin = pos + n * (1e-3 * uVoxelSize);
    ray.dir = normalize(uLightDir);
    vec3 lo = uGridOrigin, hi = uGridOrigin + vec3(uGridSize) * uVoxelSize;
    vec3 invDir = vec3(ray.dir.x != 0.0 ? 1.0 / ray.dir.x : 1e30, ray.dir.y != 0.0 ? 1.0 / ray.dir.y : 1e30,
                       ray.dir.z != 0.0 ? 1.0 / ray.dir.z : 1e30);
    vec3 ta = (lo - ray.origin) * invDir, tb = (hi - ray.origin) * invDir;
    vec3 tNear3 = min(ta, tb), tFar3 = max(ta, tb);
    float tEnter = max(max(tNear3.x, tNear3.y), max(tNear3.z, 0.0));
    float tFar = min(min(tFar3.x, tFar3.y), tFar3.z);
    if (!(tEnter < tFar)) return 1.0;
    vec3 g = (ray.origin + tEnter * ray.dir - uGridOrigin) / uVoxelSize;
    ivec3 v = clamp(ivec3(floor(g)), ivec3(0), uGridSize - 1);
    ivec3 stepDir = ivec3(sign(ray.dir));
    vec3 tDelta = abs(uVoxelSize * invDir);
    vec3 tMax;
    for (int k = 0; k < 3; ++k) {
        float face = uGridOrigin[k] + float(v[k] + (stepDir[k] > 0 ? 1 : 0)) * uVoxelSize;
        tMax[k] = stepDir[k] == 0 ? 1e30 : (face - ray.origin[k]) * invDir[k];
    }
    for (int steps = 0; steps < 8192; ++steps) {
        float tExit = min(min(tMax.x, tMax.y), tMax.z);
#ifdef NEIGHBORS
        if ((vrcHeaderCount((v.z * uGridSize.y + v.y) * uGridSize.x + v.x) & kVrcNeighbourhoodBit) != 0u)
            for (int k = 0; k < 27; ++k)
                if (vrcShadowRayHitsVoxel(ray, v + ivec3(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1), tEnter, tExit))
                    return 0.0;
#else
        if (vrcShadowRayHitsVoxel(ray, v, tEnter, tExit)) return 0.0;
#endif
        if (tMax.x <= tMax.y && tMax.x <= tMax.z) {
            v.x += stepDir.x;
            tMax.x += tDelta.x;
        } else if (tMax.y <= tMax.z) {
            v.y += stepDir.y;
            tMax.y += tDelta.y;
        } else {
            v.z += stepDir.z;
            tMax.z += tDelta.z;
        }
        tEnter = tExit;
        if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, uGridSize)) || tEnter > tFar) break;
    }
    return 1.0;
}
#endif

#ifndef VRC_AO_PRECOMPUTE
// The lighting of a hit at pos with outward normal n on the piece (end0, end1) of opacity alpha:
// replaces ao and visibility where the defines above ask for it (vrc_raycast.comp, shadeHit).
void vrcLighting(vec3 pos, vec3 n, vec3 facing, vec4 end0, vec4 end1, float alpha, inout float ao,
                 inout float visibility) {
    VrcOwnLine own = vrcOwnLine(end0, end1, alpha);
#ifdef VRC_DENSITY_AO
    ao = vrcDensityRayAmbientOcclusion(pos, facing, own);
#endif
#ifdef VRC_PRECOMPUTED_AO
    ao = vrcPrecomputedAmbientOcclusion(pos);
#endif
#ifdef VRC_DENSITY_SHADOWS
    visibility = 1.0 - vrcDensityConeOcclusion(pos, normalize(uLightDir), own);
#endif
#ifdef VRC_HARD_TUBE_SHADOWS
    visibility = vrcHardTubeVisibility(pos, n);
#endif
}
#endif
