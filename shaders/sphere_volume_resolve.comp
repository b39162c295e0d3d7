// Fixed-point sphere coverage (sphere_voxelize.comp) -> level 0 of the RGBA32F volume: alpha =
// coverage x opacity (1 = a voxel filled by opaque spheres; sums of overlapping spheres may
// exceed 1), rgb = the same times colour (premultiplied). Clears the accumulator for next time.
layout(local_size_x = 64) in;

layout(std430, binding = SSBO_SPHERE_ACCUMULATOR) buffer Accumulator { uint accumulator[]; };
layout(binding = IMAGE_SPHERE_VOLUME_OUT, rgba32f) uniform writeonly image3D uVolume;

uniform ivec3 uSize;

const double kFullCoverage = 27.0LF * 65536.0LF;  // sphere_voxelize.comp

// The 64-bit sum at accumulator[i] (low), [i + 1] (high), exact in a double below 2^53.
double wide(int i) {
    return double(accumulator[i + 1]) * 4294967296.0LF + double(accumulator[i]);
}

void main() {
    // 2D dispatch: a 256^3 grid needs more than the 65535 groups one dimension guarantees.
    int v = int((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x);
    if (v >= uSize.x * uSize.y * uSize.z) return;
    // Divisions in double, not a multiplication by a reciprocal: a full voxel reads exactly 1, and
    // the CPU twin (rt/particle_ambient.cpp) rounds the same quotient to the same float.
    dvec4 sums = dvec4(wide(8 * v), wide(8 * v + 2), wide(8 * v + 4), wide(8 * v + 6));
    vec4 value = vec4(sums / dvec4(dvec3(kFullCoverage * 255.0LF * 255.0LF), kFullCoverage * 255.0LF));
    ivec3 p = ivec3(v % uSize.x, (v / uSize.x) % uSize.y, v / (uSize.x * uSize.y));
    imageStore(uVolume, p, value);
    for (int k = 0; k < 8; ++k) accumulator[8 * v + k] = 0u;
}
