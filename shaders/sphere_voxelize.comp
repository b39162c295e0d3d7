// Voxelization of sphere glyphs for ambient occlusion and ambient light (Staib et al. 2015,
// Sect. 5.1), one invocation per sphere over the voxels its bounding box touches. The overlap
// weight w of a sphere and a voxel, as the paper's three cases:
//   - the voxel contains the whole sphere: w = the fraction of the voxel the sphere fills,
//     4/3 pi r^3 in voxel units (so spheres far smaller than a voxel add their volume);
//   - the sphere contains the whole voxel (its farthest corner inside): w = 1;
//   - else (a partial overlap): the fraction of the 3x3x3 sub-voxel centres inside the sphere.
// Disjoint voxels (the box's nearest point outside) get nothing. w is fixed point with
// kFullCoverage units per voxel: 2^16 per sub-sample, so the sampled cases are exact and a
// contained sphere is rounded to 1 / (27 x 2^16) ~ 5.7e-7 voxel. Accumulated with integer atomics
// (GL has no float atomics on llvmpipe, and integer sums do not depend on the order): per voxel
// four 64-bit sums, each two uints (low, high), rgb += w x opacity255 x colour255,
// a += w x opacity255, which sphere_volume_resolve.comp turns into premultiplied RGBA coverage.
// rt/particle_ambient.cpp (SphereVolume) is the CPU twin: same weights, same sums.
layout(local_size_x = 64) in;

layout(std430, binding = SSBO_SPHERE_CENTER_RADIUS) readonly buffer CenterRadius { vec4 centerRadius[]; };
layout(std430, binding = SSBO_SPHERE_COLORS) readonly buffer Colors { vec4 colors[]; };
layout(std430, binding = SSBO_SPHERE_ACCUMULATOR) buffer Accumulator { uint accumulator[]; };

uniform uint uFirst;
uniform uint uCount;
uniform vec3 uOrigin;
uniform float uVoxelSize;
uniform ivec3 uSize;
#ifdef DENSITY_OWNER
// Data-parallel rendering: only the spheres whose centre lies in this rank's region box
// [uOwnerLo, uOwnerHi) deposit, so the sum over ranks counts each sphere once (core/region.h
// RegionSetup::densityOwner).
uniform vec3 uOwnerLo;
uniform vec3 uOwnerHi;
#endif

// The ambient transfer functions (Staib et al. 2015, Sect. 3.2; core/scene.h AmbientTransfer):
// piecewise linear over the particle opacity; a count of 0 is the identity.
const int kMaxAmbientPoints = 16;
uniform int uAmbientOpacityCount;
uniform vec2 uAmbientOpacity[kMaxAmbientPoints];
uniform int uAmbientEmissionCount;
uniform vec2 uAmbientEmission[kMaxAmbientPoints];

// The transfer function's value at t (ambientTransferAt of core/sphere_glyph.cpp, same order).
float ambientTransferAt(vec2 points[kMaxAmbientPoints], int count, float t) {
    if (t <= points[0].x) return points[0].y;
    for (int i = 1; i < count; ++i)
        if (t <= points[i].x) {
            precise float w = points[i].x - points[i - 1].x;
            if (!(w > 0.0)) return points[i].y;
            precise float s = (t - points[i - 1].x) / w;
            precise float v = points[i - 1].y * (1.0 - s) + points[i].y * s;
            return v;
        }
    return points[count - 1].y;
}

// tc::ambientClassify: the colour x e_A(Theta), the opacity Theta_A(Theta), Theta = color.a.
vec4 ambientClassify(vec4 color) {
    vec4 c = color;
    if (uAmbientEmissionCount > 0) c.rgb = color.rgb * ambientTransferAt(uAmbientEmission, uAmbientEmissionCount, color.a);
    if (uAmbientOpacityCount > 0) c.a = ambientTransferAt(uAmbientOpacity, uAmbientOpacityCount, color.a);
    return c;
}

const uint kUnitsPerSample = 65536u;
const uint kFullCoverage = 27u * kUnitsPerSample;
const float kSphereVolume = 4.18879020;  // 4/3 pi

// accumulator[i] (low) and [i + 1] (high) += high:low. The one add that wraps the low word sees
// old + low < old and carries into the high word, so the pair sums exactly whatever the order.
void addWide(uint i, uint high, uint low) {
    uint old = atomicAdd(accumulator[i], low);
    if (old + low < old) high += 1u;
    if (high != 0u) atomicAdd(accumulator[i + 1u], high);
}

void main() {
    uint i = uFirst + gl_GlobalInvocationID.x;
    if (i >= uCount) return;
    vec4 cr = centerRadius[i];
#ifdef DENSITY_OWNER
    if (!(all(greaterThanEqual(cr.xyz, uOwnerLo)) && all(lessThan(cr.xyz, uOwnerHi)))) return;
#endif
    vec4 color = clamp(ambientClassify(clamp(colors[i], vec4(0.0), vec4(1.0))), vec4(0.0), vec4(1.0));
    uint opacity = uint(round(color.a * 255.0));
    if (opacity == 0u) return;
    uvec3 rgb = uvec3(round(color.rgb * 255.0));
    vec3 c = (cr.xyz - uOrigin) / uVoxelSize;  // in voxels
    float r = cr.w / uVoxelSize;
    float r2 = r * r;
    ivec3 lo = max(ivec3(floor(c - r)), ivec3(0));
    ivec3 hi = min(ivec3(floor(c + r)), uSize - 1);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
                vec3 vlo = vec3(x, y, z), vhi = vlo + 1.0;
                vec3 nearest = clamp(c, vlo, vhi) - c;
                if (dot(nearest, nearest) >= r2) continue;
                vec3 farthest = max(abs(vlo - c), abs(vhi - c));
                uint w = kFullCoverage;
                if (all(greaterThanEqual(c - r, vlo)) && all(lessThanEqual(c + r, vhi))) {
                    // precise and roundEven (not floor(x + 0.5)): the products in this order, none
                    // fused or regrouped, as the CPU twin computes them.
                    precise float units = kSphereVolume * r * r * r * float(kFullCoverage);
                    w = uint(roundEven(units));
                } else if (dot(farthest, farthest) > r2) {
                    uint n = 0u;
                    for (int k = 0; k < 27; ++k) {
                        vec3 s = vlo + (vec3(k % 3, (k / 3) % 3, k / 9) + 0.5) / 3.0 - c;
                        n += dot(s, s) < r2 ? 1u : 0u;
                    }
                    w = n * kUnitsPerSample;
                }
                if (w == 0u) continue;
                uint v = 8u * uint(x + uSize.x * (y + uSize.y * z));
                uint wo = w * opacity;  // < 2^29
                uint high, low;
                umulExtended(wo, rgb.r, high, low);
                addWide(v + 0u, high, low);
                umulExtended(wo, rgb.g, high, low);
                addWide(v + 2u, high, low);
                umulExtended(wo, rgb.b, high, low);
                addWide(v + 4u, high, low);
                addWide(v + 6u, 0u, wo);
            }
}
