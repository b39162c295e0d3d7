// One level of the density mip pyramid (gl/density_volume.cpp): every texel of level L+1 is the
// area-weighted average of level L over the same texture-coordinate box, so each level keeps the
// mean of level 0 for any grid size (see gl/density_volume.h).
//
// Per axis, with nf texels at level L and nc = max(1, nf / 2) at level L+1, coarse texel i covers
// the fine interval [i * nf / nc, (i + 1) * nf / nc). In units of 1 / nc that is [i * nf,
// (i + 1) * nf) and fine texel j is [j * nc, (j + 1) * nc), so overlaps are exact integers and
// the weights overlap / nf sum to exactly 1: 0.5, 0.5 for even nf; up to 4 taps for odd nf.
//
// Defines: DENSITY_IMAGE_FORMAT (r32f or r16f), the format of both image bindings; MIP_RGBA to
// filter all four channels (rgba32f sphere volumes of gl/sphere_ambient.cpp) instead of red only.
#ifdef MIP_RGBA
#define MIP_VALUE vec4
#define MIP_LOAD(p) imageLoad(uSource, p)
#define MIP_STORE(v) (v)
#else
#define MIP_VALUE float
#define MIP_LOAD(p) imageLoad(uSource, p).r
#define MIP_STORE(v) vec4(v, 0.0, 0.0, 0.0)
#endif
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(binding = IMAGE_MIP_SOURCE, DENSITY_IMAGE_FORMAT) uniform readonly image3D uSource;  // level L
layout(binding = IMAGE_MIP_TARGET, DENSITY_IMAGE_FORMAT) uniform writeonly image3D uTarget;  // level L + 1

uniform ivec3 uSourceSize;
uniform ivec3 uTargetSize;

const int kMaxTaps = 4;

struct Taps {
    int first;
    int count;
    float weights[kMaxTaps];
};

Taps axisTaps(int i, int nf, int nc)
{
    Taps taps;
    int lo = i * nf;
    int hi = lo + nf;
    taps.first = lo / nc;
    int last = (hi + nc - 1) / nc;  // one past the last fine texel touched
    taps.count = min(last - taps.first, kMaxTaps);
    for (int k = 0; k < kMaxTaps; ++k) {
        int j = taps.first + k;
        int overlap = min(hi, (j + 1) * nc) - max(lo, j * nc);
        taps.weights[k] = k < taps.count ? float(overlap) / float(nf) : 0.0;
    }
    return taps;
}

void main()
{
    ivec3 target = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(target, uTargetSize)))
        return;
    if (uSourceSize == 2 * uTargetSize) {
        // Every axis even (all levels of a power-of-two grid): the plain 2x2x2 box, same
        // weights and order as the general path below would use.
        ivec3 s = 2 * target;
        MIP_VALUE sum = MIP_VALUE(0.0);
        for (int z = 0; z < 2; ++z) {
            MIP_VALUE plane = MIP_VALUE(0.0);
            for (int y = 0; y < 2; ++y) {
                MIP_VALUE row = MIP_VALUE(0.0);
                for (int x = 0; x < 2; ++x)
                    row += 0.5 * MIP_LOAD(s + ivec3(x, y, z));
                plane += 0.5 * row;
            }
            sum += 0.5 * plane;
        }
        imageStore(uTarget, target, MIP_STORE(sum));
        return;
    }
    Taps tx = axisTaps(target.x, uSourceSize.x, uTargetSize.x);
    Taps ty = axisTaps(target.y, uSourceSize.y, uTargetSize.y);
    Taps tz = axisTaps(target.z, uSourceSize.z, uTargetSize.z);
    // Fixed summation order (z, y, x), so the pyramid is bit-identical run to run.
    MIP_VALUE sum = MIP_VALUE(0.0);
    for (int z = 0; z < tz.count; ++z) {
        MIP_VALUE plane = MIP_VALUE(0.0);
        for (int y = 0; y < ty.count; ++y) {
            MIP_VALUE row = MIP_VALUE(0.0);
            for (int x = 0; x < tx.count; ++x)
                row += tx.weights[x] * MIP_LOAD(ivec3(tx.first + x, ty.first + y, tz.first + z));
            plane += ty.weights[y] * row;
        }
        sum += tz.weights[z] * plane;
    }
    imageStore(uTarget, target, MIP_STORE(sum));
}
