// Voxelization of sphere glyphs for ambient occlusion and ambient light (Staib et al. 2015,
// Sect. 5.1), one invocation per sphere over the voxels its bounding box touches. Coverage of a
// voxel, in 27ths: 27 when the voxel lies inside the sphere (its farthest corner inside), 0 when
// they are disjoint (the box's nearest point outside), else the number of 3x3x3 sub-sample points
// (sub-voxel centres) inside. Accumulated with integer atomics (GL has no float atomics on
// llvmpipe): per voxel 4 uints, rgb += n * opacity255 * colour255, a += n * opacity255, which
// sphere_volume_resolve.comp turns into premultiplied RGBA coverage.
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

void main() {
    uint i = uFirst + gl_GlobalInvocationID.x;
    if (i >= uCount) return;
    vec4 cr = centerRadius[i];
#ifdef DENSITY_OWNER
    if (!(all(greaterThanEqual(cr.xyz, uOwnerLo)) && all(lessThan(cr.xyz, uOwnerHi)))) return;
#endif
    vec4 color = clamp(colors[i], vec4(0.0), vec4(1.0));
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
                uint n = 27u;
                if (dot(farthest, farthest) > r2) {
                    n = 0u;
                    for (int k = 0; k < 27; ++k) {
                        vec3 s = vlo + (vec3(k % 3, (k / 3) % 3, k / 9) + 0.5) / 3.0 - c;
                        n += dot(s, s) < r2 ? 1u : 0u;
                    }
                    if (n == 0u) continue;
                }
                uint v = 4u * uint(x + uSize.x * (y + uSize.y * z));
                uint w = n * opacity;
                atomicAdd(accumulator[v + 0u], w * rgb.r);
                atomicAdd(accumulator[v + 1u], w * rgb.g);
                atomicAdd(accumulator[v + 2u], w * rgb.b);
                atomicAdd(accumulator[v + 3u], w);
            }
}
