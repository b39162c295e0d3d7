// Fixed-point sphere coverage (sphere_voxelize.comp) -> level 0 of the RGBA32F volume: alpha =
// coverage x opacity (1 = a voxel filled by opaque spheres; sums of overlapping spheres may
// exceed 1), rgb = the same times colour (premultiplied). Clears the accumulator for next time.
layout(local_size_x = 64) in;

layout(std430, binding = SSBO_SPHERE_ACCUMULATOR) buffer Accumulator { uint accumulator[]; };
layout(binding = IMAGE_SPHERE_VOLUME_OUT, rgba32f) uniform writeonly image3D uVolume;

uniform ivec3 uSize;

void main() {
    // 2D dispatch: a 256^3 grid needs more than the 65535 groups one dimension guarantees.
    int v = int((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x);
    if (v >= uSize.x * uSize.y * uSize.z) return;
    uvec4 a = uvec4(accumulator[4 * v], accumulator[4 * v + 1], accumulator[4 * v + 2], accumulator[4 * v + 3]);
    // Divisions, not a multiplication by 1/(27 x 255): a full voxel must read exactly 1.
    vec4 value = vec4(vec3(a.rgb) / (27.0 * 255.0 * 255.0), float(a.a) / (27.0 * 255.0));
    ivec3 p = ivec3(v % uSize.x, (v / uSize.x) % uSize.y, v / (uSize.x * uSize.y));
    imageStore(uVolume, p, value);
    accumulator[4 * v] = 0u;
    accumulator[4 * v + 1] = 0u;
    accumulator[4 * v + 2] = 0u;
    accumulator[4 * v + 3] = 0u;
}
