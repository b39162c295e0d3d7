// Voxel cone traced ambient occlusion for lines (Groß & Gumhold 2020, Sect. 5.3; cone tracing of
// Crassin et al. 2011 and Staib et al. 2015) over the density volume of gl/density_volume.h.
// gl::DensityVolume::setUniforms sets the uniforms below; bind the volume to the unit uDensity
// names (DensityVolume::bind).
//
// Occlusion model. A density rho (core/voxel_density.h: fraction of a voxel's volume filled by
// tube, times opacity) is read as "a ray crossing one level-0 voxel of this material is blocked
// with probability rho". A step of length d through a region of mean density rho then has opacity
//     alpha = 1 - (1 - rho)^(strength * d / voxelSize)                                  (1)
// with voxelSize the level-0 voxel size at every mip level, so in a uniform region the result
// does not depend on how the cone is cut into steps. Densities above 1 (overlapping tubes) are
// clamped to 1 before (1); the mip pyramid averages the unclamped values, which keeps totals.
//
// Cone marching. From t = startOffset each step is one cone diameter long,
// d = max(2 t tan(aperture / 2), voxelSize), the last one cut at maxDistance; the step is sampled
// at its middle with textureLod(level = log2(d / voxelSize)) so the filter footprint matches the
// cone (quadrilinear). Front to back: occ += (1 - occ) * alpha, stopping at maxDistance or
// occ > 0.99.
//
// Self-occlusion. A tube deposits its whole cross-section into the voxels holding its axis
// (core/voxel_density.h), and a quadrilinear read at level log2(d) reaches 1.5 texels (up to
// 1.5 * 2^ceil(lod) * sqrt(3) voxels) around the sample: at 50 degrees every step of a cone
// reads the shaded tube's own deposit (about pi r^2 / d^2 per step d, a geometric series
// dominated by the first steps), so an isolated tube would darken itself. No start offset fixes
// that without hiding the near field that makes bundles dark, and excluding texels by level
// (the reach of a level against the tangent plane, the former approach) switched levels with the
// normal and made AO jump with it (0.33 / 0.67 / 0.00 at 28 / 51 / 62 degrees on one tube).
// So the tracer takes the shaded tube (ConeOwnTube: its axis as an infinite line and an upper
// bound on its deposit per voxel of axis length, pi r^2 alpha / voxelSize^2) and, at the steps
// whose 2x2x2 texel blocks can reach that line, filters by hand: each texel loses the deposit the
// line leaves in it (deposit x length of the line inside the texel's box / texel volume, exact
// for the voxelizer's per-voxel pieces and for mip levels that halve evenly), clamped at 0, with
// the weights of GL_LINEAR_MIPMAP_LINEAR. Every term is continuous in the sample position, so AO
// is a continuous function of the normal, and an isolated straight tube reads exactly 1. Other
// tubes in the same texels keep their density. The infinite line also removes the polyline's
// straight continuation; a bend's neighbouring segment stays (on the inner side it is real
// occlusion). Without an own tube (spheres' test volumes, hand-made grids) the read is plain.
//
// Cone sets, around the normal n, deterministic (no per-pixel rotation, so no noise and
// bit-identical frames); azimuth 0 is the shaded tube's axis projected onto the tangent plane
// (continuous as the normal turns around the tube; within ~15 degrees of the axis, at the poles
// of end caps, and without an own tube: the tangent frame of Duff et al. 2017 built from n):
//   cones = 1     one cone along n;
//   cones = 2..5  a ring of `cones` cones at 45 degrees from n (the median polar angle of a
//                 cosine-weighted hemisphere: sin^2 = 1/2), evenly spaced in azimuth;
//   cones >= 6    one cone along n plus a ring of cones - 1 at 60 degrees (the 6-cone set of the
//                 VCT literature when cones = 6).
// AO = 1 - sum_i w_i occ_i / sum_i w_i with w_i = cos(polar angle of cone i) (cosine-weighted
// hemisphere; equal weights within a ring).

uniform sampler3D uDensity;
uniform vec3 uDensityOrigin;
uniform float uDensityVoxelSize;  // level 0, world units
uniform ivec3 uDensitySize;       // level 0, voxels
uniform int uDensityLevels;

const float kConeOcclusionCutoff = 0.99;
const int kConeMaxSteps = 128;  // a 10-degree cone over 1024 voxels takes ~40 steps
// Relative margin on the own tube's deposit: the mip sums and the fixed-point deposits round in
// the last bits, and a residual of 1e-7 of a tube's density would keep an isolated tube from
// reading exactly 1.
const float kConeOwnMargin = 1.001;
// Texel boxes are grown by this many level-0 voxels when the own line is clipped to them: an axis
// on a voxel face (a common case: grids centred on the data) goes to one side in the voxelizer's
// double precision and may land on the other in float here; the grown boxes remove it from both.
const float kConeOwnSlack = 1e-3;

// The shaded tube (see "Self-occlusion"): a point on its axis and the unit axis direction, world
// space, and its deposit per voxel of axis length, pi r^2 alpha / voxelSize^2 (an upper bound
// over the segment). density 0: nothing is excluded.
struct ConeOwnTube {
    vec3 origin;
    vec3 dir;
    float density;
};

ConeOwnTube coneNoOwnTube() { return ConeOwnTube(vec3(0.0), vec3(0.0, 0.0, 1.0), 0.0); }

// The own tube of a rounded cone from a to b (xyz world, w radius) with opacities alphaA, alphaB:
// its deposit per voxel of axis length is pi r(s)^2 alpha(s) / voxelSize^2 (core/voxel_density.h),
// bounded by the larger radius and opacity.
ConeOwnTube coneOwnTube(vec4 a, vec4 b, float alphaA, float alphaB) {
    vec3 d = b.xyz - a.xyz;
    float len2 = dot(d, d);
    float r = max(a.w, b.w) / uDensityVoxelSize;
    return ConeOwnTube(a.xyz, len2 > 0.0 ? d * inversesqrt(len2) : vec3(0.0, 0.0, 1.0),
                       len2 > 0.0 ? 3.14159265 * r * r * clamp(max(alphaA, alphaB), 0.0, 1.0) : 0.0);
}

// Branchless orthonormal basis around unit n (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"): continuous except across n.z = 0's sign switch, no division by zero.
void coneTangentFrame(vec3 n, out vec3 t, out vec3 b)
{
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// Mean density around world position p over a box of about 2^lod level-0 voxels.
float coneDensity(vec3 p, float lod)
{
    vec3 uvw = (p - uDensityOrigin) / (uDensityVoxelSize * vec3(uDensitySize));
    return textureLod(uDensity, uvw, lod).r;
}

// Texel width of mip level `level` per axis, in level-0 voxels (size / levelSize: texel i of a
// level covers [i w, (i + 1) w) of level 0 with the area-weighted taps of density_mip.comp).
vec3 coneTexelWidth(int level)
{
    return vec3(uDensitySize) / vec3(max(uDensitySize >> level, ivec3(1)));
}

// One level's trilinear read at pv (level-0 voxel coordinates) with the zero border of the
// texture, each texel less the own line's deposit in it (clamped at 0): the length of the line
// o + s u inside the texel's box (slab test; invU = 1 / u with zeros replaced by huge values, |u|
// = 1) times ownDensity (per voxel of length, with the margin) / texel volume. The block's lower
// and upper slab along each axis are clipped once and combined per texel.
float coneLevelDensityExcluding(vec3 pv, int level, vec3 o, vec3 invU, float ownDensity)
{
    ivec3 n = max(uDensitySize >> level, ivec3(1));
    vec3 w = vec3(uDensitySize) / vec3(n);
    vec3 c = pv / w - 0.5;
    vec3 base = floor(c);
    vec3 f = c - base;
    ivec3 i0 = ivec3(base);
    float perLength = ownDensity / (w.x * w.y * w.z);
    vec3 lo0 = base * w - kConeOwnSlack, hi0 = lo0 + w + 2.0 * kConeOwnSlack;
    vec3 a0 = (lo0 - o) * invU, b0 = (hi0 - o) * invU, a1 = (lo0 + w - o) * invU, b1 = (hi0 + w - o) * invU;
    vec3 near0 = min(a0, b0), far0 = max(a0, b0), near1 = min(a1, b1), far1 = max(a1, b1);
    float sum = 0.0;
    for (int k = 0; k < 8; ++k) {
        ivec3 d = ivec3(k & 1, (k >> 1) & 1, k >> 2);
        ivec3 i = i0 + d;
        if (any(lessThan(i, ivec3(0))) || any(greaterThanEqual(i, n))) continue;
        bvec3 upper = bvec3(d);
        vec3 w3 = mix(1.0 - f, f, vec3(d));
        vec3 tNear = mix(near0, near1, upper), tFar = mix(far0, far1, upper);
        float len = max(min(min(tFar.x, tFar.y), tFar.z) - max(max(tNear.x, tNear.y), tNear.z), 0.0);
        float texel = texelFetch(uDensity, i, level).r;
        sum += w3.x * w3.y * w3.z * max(texel - perLength * len, 0.0);
    }
    return sum;
}

// Density read at world position p and mip level lod (the cone's diameter), without the own
// tube's deposit where the read can reach it.
float coneDensityExcluding(vec3 p, float lod, ConeOwnTube own)
{
    if (own.density <= 0.0) return coneDensity(p, lod);
    int l0 = int(floor(lod));
    int l1 = min(l0 + 1, max(uDensityLevels - 1, 0));
    float frac = lod - float(l0);
    int reachLevel = frac > 0.0 ? l1 : l0;
    // A 2x2x2 block of level l spans at most 1.5 texels from p on every axis: a line farther than
    // the half-diagonal of that box leaves nothing in it, and the plain read is the same filter.
    vec3 pv = (p - uDensityOrigin) / uDensityVoxelSize;
    vec3 o = (own.origin - uDensityOrigin) / uDensityVoxelSize;
    vec3 rel = pv - o;
    float dist = length(rel - dot(rel, own.dir) * own.dir);
    if (dist > 1.5 * length(coneTexelWidth(reachLevel))) return coneDensity(p, lod);
    vec3 invU = 1.0 / mix(own.dir, vec3(1e-20), lessThan(abs(own.dir), vec3(1e-20)));
    float ownDensity = own.density * kConeOwnMargin;
    float rho = coneLevelDensityExcluding(pv, l0, o, invU, ownDensity);
    if (frac > 0.0 && l1 != l0) rho = mix(rho, coneLevelDensityExcluding(pv, l1, o, invU, ownDensity), frac);
    return rho;
}

// Occlusion in [0, 1] of one cone with apex `apex` and unit axis `dir`, excluding `own`.
float traceOcclusionCone(vec3 apex, vec3 dir, float tanHalfAperture, float maxDistance, float strength,
                         float startOffset, ConeOwnTube own)
{
    float maxLod = float(max(uDensityLevels - 1, 0));
    float occlusion = 0.0;
    float t = startOffset;
    for (int i = 0; i < kConeMaxSteps && t < maxDistance && occlusion <= kConeOcclusionCutoff; ++i) {
        float diameter = max(2.0 * t * tanHalfAperture, uDensityVoxelSize);
        float stepLength = min(diameter, maxDistance - t);
        float lod = clamp(log2(diameter / uDensityVoxelSize), 0.0, maxLod);
        float rho = clamp(coneDensityExcluding(apex + (t + 0.5 * stepLength) * dir, lod, own), 0.0, 1.0);
        // Eq. (1) as exp2(e * log2(1 - rho)); the floor keeps log2 finite at rho = 1
        // (2^-100 per voxel is full occlusion) and strength = 0 at exactly no occlusion.
        float transmittance =
            exp2(strength * stepLength / uDensityVoxelSize * log2(max(1.0 - rho, 1e-30)));
        occlusion += (1.0 - occlusion) * (1.0 - transmittance);
        t += stepLength;
    }
    return occlusion;
}

// Ambient occlusion factor at `position` on the surface of tube `own` with unit-or-not `normal`:
// 1 = unoccluded, 0 = fully occluded. `apertureRad` is each cone's full apex angle; `maxDistance`
// and `startOffset` are in world units along the cone axis. cones <= 0 returns 1.
float coneTracedTubeOcclusion(vec3 position, vec3 normal, ConeOwnTube own, int cones, float apertureRad,
                              float maxDistance, float strength, float startOffset)
{
    if (cones <= 0)
        return 1.0;
    vec3 n = normalize(normal);
    vec3 tangent, bitangent;
    vec3 along = own.dir - dot(own.dir, n) * n;
    if (own.density > 0.0 && dot(along, along) > 0.0625) {  // the axis >= ~15 degrees off n
        tangent = normalize(along);
        bitangent = cross(n, tangent);
    } else {
        coneTangentFrame(n, tangent, bitangent);
    }
    float tanHalfAperture = tan(0.5 * apertureRad);

    bool central = cones == 1 || cones >= 6;
    int ringCones = central ? cones - 1 : cones;
    float ringPolar = cones >= 6 ? radians(60.0) : radians(45.0);
    float ringCos = cos(ringPolar), ringSin = sin(ringPolar);

    float visible = 0.0, weightSum = 0.0;
    if (central) {
        visible += 1.0 - traceOcclusionCone(position, n, tanHalfAperture, maxDistance, strength, startOffset, own);
        weightSum += 1.0;
    }
    for (int i = 0; i < ringCones; ++i) {
        float phi = 6.28318530718 * float(i) / float(ringCones);
        vec3 dir = ringCos * n + ringSin * (cos(phi) * tangent + sin(phi) * bitangent);
        visible += ringCos * (1.0 - traceOcclusionCone(position, dir, tanHalfAperture, maxDistance, strength,
                                                       startOffset, own));
        weightSum += ringCos;
    }
    return visible / weightSum;
}

// coneTracedTubeOcclusion without a shaded tube to exclude.
float coneTracedOcclusion(vec3 position, vec3 normal, int cones, float apertureRad, float maxDistance,
                          float strength, float startOffset)
{
    return coneTracedTubeOcclusion(position, normal, coneNoOwnTube(), cones, apertureRad, maxDistance, strength,
                                   startOffset);
}
