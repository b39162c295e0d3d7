#pragma once
// A 3D texture with its full mip pyramid on the CPU, filtered as GL filters the GPU's density
// volumes (shaders/density_mip.comp, GL_LINEAR_MIPMAP_LINEAR with CLAMP_TO_BORDER, border 0), so
// CPU cone tracing (rt/) sees the values the shaders see. T is float (line density) or glm::vec4
// (the particles' RGBA volume). Level L + 1 has max(1, n / 2) texels per axis; each coarse texel
// is the area-weighted average of the fine texels it covers (exact integer overlaps, summed in the
// shader's order z, y, x). Hand-written rather than OpenImageIO's 2D mip maps: 3D, odd sizes and
// the shader's exact taps and summation order.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <glm/glm.hpp>
#include <vector>

namespace tc {

// Levels of a full pyramid over `size` (gl::DensityVolume::fullLevels uses it): 1 + floor(log2(longest)).
inline int fullMipLevels(const glm::ivec3& size) {
    int longest = std::max({size.x, size.y, size.z});
    int levels = 1;
    while (longest >>= 1) ++levels;
    return levels;
}

template <class T>
class MipPyramid {
public:
    MipPyramid() = default;
    // Level 0 is `level0` (size.x fastest); the coarser levels are built from it (oneTBB).
    MipPyramid(const glm::ivec3& size, std::vector<T> level0);

    int levels() const { return int(m_levels.size()); }
    glm::ivec3 levelSize(int level) const { return m_sizes[std::size_t(level)]; }
    const glm::ivec3& size() const { return m_sizes[0]; }
    // Texel (x, y, z) of `level`, zero outside (the border colour).
    T texel(int level, int x, int y, int z) const {
        const glm::ivec3 s = m_sizes[std::size_t(level)];
        if (x < 0 || y < 0 || z < 0 || x >= s.x || y >= s.y || z >= s.z) return T(0.0f);
        return m_levels[std::size_t(level)][(std::size_t(z) * s.y + std::size_t(y)) * s.x + std::size_t(x)];
    }
    // One level, trilinear between texel centres; uvw in [0, 1]^3 over the grid.
    T sampleLevel(const glm::vec3& uvw, int level) const;
    // GL textureLod(sampler3D, uvw, lod).
    T textureLod(const glm::vec3& uvw, float lod) const;
    std::size_t bytes() const {
        std::size_t b = 0;
        for (const auto& l : m_levels) b += l.size() * sizeof(T);
        return b;
    }

private:
    std::vector<std::vector<T>> m_levels;
    std::vector<glm::ivec3> m_sizes;
};

namespace detail {

constexpr int kMaxMipTaps = 4;

// axisTaps of shaders/density_mip.comp: coarse texel i of nc covers fine texels [i nf / nc,
// (i + 1) nf / nc) with exact integer overlaps.
struct MipTaps {
    int first = 0, count = 0;
    float weights[kMaxMipTaps] = {0, 0, 0, 0};
};
inline MipTaps mipAxisTaps(int i, int nf, int nc) {
    MipTaps taps;
    const int lo = i * nf, hi = lo + nf;
    taps.first = lo / nc;
    const int last = (hi + nc - 1) / nc;
    taps.count = std::min(last - taps.first, kMaxMipTaps);
    for (int k = 0; k < kMaxMipTaps; ++k) {
        const int j = taps.first + k;
        const int overlap = std::min(hi, (j + 1) * nc) - std::max(lo, j * nc);
        taps.weights[k] = k < taps.count ? float(overlap) / float(nf) : 0.0f;
    }
    return taps;
}

}  // namespace detail

template <class T>
MipPyramid<T>::MipPyramid(const glm::ivec3& size, std::vector<T> level0) {
    const int levels = fullMipLevels(size);
    m_sizes.push_back(size);
    m_levels.push_back(std::move(level0));
    for (int l = 0; l + 1 < levels; ++l) {
        const glm::ivec3 nf = m_sizes.back();
        const glm::ivec3 nc = glm::max(glm::ivec3(1), nf / 2);
        std::vector<T> coarse(std::size_t(nc.x) * nc.y * nc.z);
        const std::vector<T>& fine = m_levels.back();
        tbb::parallel_for(tbb::blocked_range<int>(0, nc.z), [&](const tbb::blocked_range<int>& zs) {
            for (int z = zs.begin(); z != zs.end(); ++z)
                for (int y = 0; y < nc.y; ++y)
                    for (int x = 0; x < nc.x; ++x) {
                        const detail::MipTaps tx = detail::mipAxisTaps(x, nf.x, nc.x),
                                              ty = detail::mipAxisTaps(y, nf.y, nc.y),
                                              tz = detail::mipAxisTaps(z, nf.z, nc.z);
                        // The shader's summation order (z, y, x), same float results for even sizes.
                        T sum(0.0f);
                        for (int k = 0; k < tz.count; ++k) {
                            T plane(0.0f);
                            for (int j = 0; j < ty.count; ++j) {
                                T row(0.0f);
                                for (int i = 0; i < tx.count; ++i)
                                    row += tx.weights[i] *
                                           fine[(std::size_t(tz.first + k) * nf.y + std::size_t(ty.first + j)) * nf.x +
                                                std::size_t(tx.first + i)];
                                plane += ty.weights[j] * row;
                            }
                            sum += tz.weights[k] * plane;
                        }
                        coarse[(std::size_t(z) * nc.y + std::size_t(y)) * nc.x + std::size_t(x)] = sum;
                    }
        });
        m_sizes.push_back(nc);
        m_levels.push_back(std::move(coarse));
    }
}

template <class T>
T MipPyramid<T>::sampleLevel(const glm::vec3& uvw, int level) const {
    const glm::vec3 c = uvw * glm::vec3(m_sizes[std::size_t(level)]) - 0.5f;
    const glm::vec3 base = glm::floor(c);
    const glm::vec3 f = c - base;
    const glm::ivec3 i0(base);
    T result(0.0f);
    for (int corner = 0; corner < 8; ++corner) {
        const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
        const float w = (dx ? f.x : 1.0f - f.x) * (dy ? f.y : 1.0f - f.y) * (dz ? f.z : 1.0f - f.z);
        if (w != 0.0f) result += w * texel(level, i0.x + dx, i0.y + dy, i0.z + dz);
    }
    return result;
}

template <class T>
T MipPyramid<T>::textureLod(const glm::vec3& uvw, float lod) const {
    if (!(lod > 0.0f)) return sampleLevel(uvw, 0);  // magnification: GL_LINEAR on the base level
    lod = std::min(lod, float(levels() - 1));
    const int l0 = int(std::floor(lod));
    const int l1 = std::min(l0 + 1, levels() - 1);
    const float f = lod - float(l0);
    const T a = sampleLevel(uvw, l0);
    return f > 0.0f && l1 != l0 ? a + f * (sampleLevel(uvw, l1) - a) : a;
}

}  // namespace tc
