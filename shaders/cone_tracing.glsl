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
// Cone marching. From t = startOffset (the caller passes about tube radius + one voxel, so a tube
// does not occlude itself) each step is one cone diameter long, d = max(2 t tan(aperture / 2),
// voxelSize), the last one cut at maxDistance; the step is sampled at its middle with
// textureLod(level = log2(d / voxelSize)) so the filter footprint matches the cone (quadrilinear).
// Front to back: occ += (1 - occ) * alpha, stopping at maxDistance or occ > 0.99.
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

// Occlusion in [0, 1] of one cone with apex `apex`, unit axis `dir`.
float traceOcclusionCone(vec3 apex, vec3 dir, float tanHalfAperture, float maxDistance,
                         float strength, float startOffset)
{
    float maxLod = float(max(uDensityLevels - 1, 0));
    float occlusion = 0.0;
    float t = startOffset;
    for (int i = 0; i < kConeMaxSteps && t < maxDistance && occlusion <= kConeOcclusionCutoff; ++i) {
        float diameter = max(2.0 * t * tanHalfAperture, uDensityVoxelSize);
        float stepLength = min(diameter, maxDistance - t);
        float lod = clamp(log2(diameter / uDensityVoxelSize), 0.0, maxLod);
        float rho = clamp(coneDensity(apex + (t + 0.5 * stepLength) * dir, lod), 0.0, 1.0);
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
        visible += 1.0 - traceOcclusionCone(position, n, tanHalfAperture, maxDistance, strength,
                                            startOffset);
        weightSum += 1.0;
    }
    for (int i = 0; i < ringCones; ++i) {
        float phi = 6.28318530718 * float(i) / float(ringCones);
        vec3 dir = ringCos * n + ringSin * (cos(phi) * tangent + sin(phi) * bitangent);
        visible += ringCos * (1.0 - traceOcclusionCone(position, dir, tanHalfAperture,
                                                       maxDistance, strength, startOffset));
        weightSum += ringCos;
    }
    return visible / weightSum;
}
