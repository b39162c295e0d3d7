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
// (core/voxel_density.h), and a quadrilinear read at level log2(d) reaches about 1.5..3 d around
// the sample (box-filtered texels of width 2^level, trilinear between their centres), further
// than the sample is from the tube's own axis at every step of a 50-degree cone: an isolated tube
// of radius 1 / 2 voxels read AO 0.82 / 0.70 with a start offset of radius + 2 voxels (grid 64,
// tests/gl/ambient_occlusion_test.cpp), and since the leaked density ~ pi r^2 / d^2 over a
// step d adds up like a geometric series from the first step, a start offset large enough to
// hide it (16+ voxels) also hides the near field that makes bundles dark. So where the read's
// footprint may reach behind the tangent plane at the apex (coneHemisphereLod: the shaded
// rounded cone is convex, so it and every texel holding its axis lie behind that plane), the
// step's density is the larger of two estimates that both exclude the shaded tube:
//   front = the read at the coarsest level whose footprint stays in front of the plane (0 if even
//           level 0's does not, within ~1.5..2.6 voxels of it): exact exclusion, but a finer,
//           alignment-dependent footprint that can miss laterally what the cone covers (a single
//           cone running parallel to a wall 4 voxels away read no occlusion with front alone);
//   own   = the read at the cone's level minus an upper bound of one straight tube of radius
//           maxRadius in it (coneOwnDensityBound, uConeOwnArea): keeps the cone's footprint.
// An isolated tube reads exactly 1 (own <= 0, front = 0). Density behind the plane is outside the
// hemisphere anyway. Polyline bends: the neighbouring segment on the inner side is real
// occlusion and stays. With uConeOwnArea = 0 the step reads max(natural, front) = natural
// except where the finer read is denser.
//
// Cone sets, around the normal n, deterministic (no per-pixel rotation, so no noise and
// bit-identical frames); directions use the tangent frame of Duff et al. 2017 built from n:
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
// Cross-section of the thickest tube, pi maxRadius^2 / voxelSize^2: the density one tube deposits
// per voxel of axis length. Set by gl::AmbientOcclusion; 0 (unset) on hand-made volumes, where no
// tube is shaded and only the hemisphere-capped read below applies.
uniform float uConeOwnArea;

const float kConeOcclusionCutoff = 0.99;
const int kConeMaxSteps = 128;  // a 10-degree cone over 1024 voxels takes ~40 steps

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

// How far behind a sample a quadrilinear read of mip level `level` can reach, measured along a
// unit normal n (nAbs = |n| componentwise), in level-0 voxels. The read at q takes the level's
// texels whose centres are within one texel width w_i of q on every axis i, and a texel holding a
// point a has its centre within w_i / 2 of a; so it never reads a texel holding a point a with
// |q_i - a_i| >= 1.5 w_i on some axis, and every point at least 1.5 * sum_i |n_i| w_i behind q
// (dot(q - a, n)) is such a point. w_i = size_i / levelSize_i is 2^level voxels for even sizes
// and up to twice that where the level has one texel along i.
float coneFootprintReach(vec3 nAbs, int level)
{
    vec3 size = vec3(uDensitySize);
    vec3 width = size / vec3(max(uDensitySize >> level, ivec3(1)));  // texel width, level-0 voxels
    return 1.5 * dot(nAbs, width);
}

// The coarsest mip level <= ceilLevel whose reach (coneFootprintReach) at a sample `height` world
// units in front of the tangent plane does not get behind the plane; -1 if even level 0's does.
int coneHemisphereLod(vec3 nAbs, float height, int ceilLevel)
{
    float h = height / uDensityVoxelSize;
    int level = ceilLevel;
    while (level >= 0 && coneFootprintReach(nAbs, level) > h)
        --level;
    return level;
}

// Upper bound on what one straight tube of cross-section uConeOwnArea adds to a quadrilinear read
// at `lod`: a texel of widths w holds at most its diagonal |w| of axis, i.e. a mean of
// area * |w| / (w_x w_y w_z); interpolation weights sum to 1 and the finer level's bound is the
// larger.
float coneOwnDensityBound(float lod)
{
    int level = int(floor(lod));
    vec3 width = vec3(uDensitySize) / vec3(max(uDensitySize >> level, ivec3(1)));
    return uConeOwnArea * length(width) / (width.x * width.y * width.z);
}

// Occlusion in [0, 1] of one cone with apex `apex`, unit axis `dir`, on the side of the tangent
// plane with unit normal `normal`.
float traceOcclusionCone(vec3 apex, vec3 dir, vec3 normal, float tanHalfAperture, float maxDistance,
                         float strength, float startOffset)
{
    float maxLod = float(max(uDensityLevels - 1, 0));
    vec3 nAbs = abs(normal);
    float cosPolar = dot(dir, normal);
    float occlusion = 0.0;
    float t = startOffset;
    for (int i = 0; i < kConeMaxSteps && t < maxDistance && occlusion <= kConeOcclusionCutoff; ++i) {
        float diameter = max(2.0 * t * tanHalfAperture, uDensityVoxelSize);
        float stepLength = min(diameter, maxDistance - t);
        float lod = clamp(log2(diameter / uDensityVoxelSize), 0.0, maxLod);
        float tSample = t + 0.5 * stepLength;
        vec3 p = apex + tSample * dir;
        float rho = coneDensity(p, lod);
        int hemisphereLod = coneHemisphereLod(nAbs, tSample * cosPolar, int(ceil(lod)));
        if (float(hemisphereLod) < lod) {
            // The read may include the shaded tube: keep what is certainly someone else's.
            float own = max(rho - coneOwnDensityBound(lod), 0.0);
            float front = hemisphereLod >= 0 ? coneDensity(p, float(hemisphereLod)) : 0.0;
            rho = max(own, front);
        }
        rho = clamp(rho, 0.0, 1.0);
        // Eq. (1) as exp2(e * log2(1 - rho)); the floor keeps log2 finite at rho = 1
        // (2^-100 per voxel is full occlusion) and strength = 0 at exactly no occlusion.
        float transmittance =
            exp2(strength * stepLength / uDensityVoxelSize * log2(max(1.0 - rho, 1e-30)));
        occlusion += (1.0 - occlusion) * (1.0 - transmittance);
        t += stepLength;
    }
    return occlusion;
}

// Ambient occlusion factor at `position` with unit-or-not `normal`: 1 = unoccluded, 0 = fully
// occluded. `apertureRad` is each cone's full apex angle; `maxDistance` and `startOffset` are in
// world units along the cone axis. cones <= 0 returns 1.
float coneTracedOcclusion(vec3 position, vec3 normal, int cones, float apertureRad,
                          float maxDistance, float strength, float startOffset)
{
    if (cones <= 0)
        return 1.0;
    vec3 n = normalize(normal);
    vec3 tangent, bitangent;
    coneTangentFrame(n, tangent, bitangent);
    float tanHalfAperture = tan(0.5 * apertureRad);

    bool central = cones == 1 || cones >= 6;
    int ringCones = central ? cones - 1 : cones;
    float ringPolar = cones >= 6 ? radians(60.0) : radians(45.0);
    float ringCos = cos(ringPolar), ringSin = sin(ringPolar);

    float visible = 0.0, weightSum = 0.0;
    if (central) {
        visible += 1.0 - traceOcclusionCone(position, n, n, tanHalfAperture, maxDistance, strength,
                                            startOffset);
        weightSum += 1.0;
    }
    for (int i = 0; i < ringCones; ++i) {
        float phi = 6.28318530718 * float(i) / float(ringCones);
        vec3 dir = ringCos * n + ringSin * (cos(phi) * tangent + sin(phi) * bitangent);
        visible += ringCos * (1.0 - traceOcclusionCone(position, dir, n, tanHalfAperture,
                                                       maxDistance, strength, startOffset));
        weightSum += ringCos;
    }
    return visible / weightSum;
}
