#pragma once
// A raw dump of what the opacity solve of one frame is built from (sorted fragment lists, parts,
// importance), so tubecast_fragment_occlusion_bench can time products and solves without GL.
// Bench-only format: native endianness, no versioning.
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/occlusion_matrix.h"
#include "core/opacity_optimization.h"

namespace tc::bench {

namespace detail {
template <class T>
void writeVector(std::FILE* f, const std::vector<T>& v) {
    const std::uint64_t size = v.size();
    std::fwrite(&size, sizeof size, 1, f);
    if (size) std::fwrite(v.data(), sizeof(T), v.size(), f);
}
template <class T>
std::vector<T> readVector(std::FILE* f) {
    std::uint64_t size = 0;
    if (std::fread(&size, sizeof size, 1, f) != 1) throw std::runtime_error("opacity system file: truncated");
    std::vector<T> v(size);
    if (size && std::fread(v.data(), sizeof(T), size, f) != size)
        throw std::runtime_error("opacity system file: truncated");
    return v;
}
}  // namespace detail

inline void saveOpacitySystem(const std::string& path, const FragmentLists& lists, const OpacityParts& parts,
                              const std::vector<double>& importance) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write " + path);
    const std::int32_t header[2] = {lists.width, parts.partsPerLine};
    std::fwrite(header, sizeof header, 1, f);
    detail::writeVector(f, lists.offsets);
    detail::writeVector(f, lists.fragments);
    detail::writeVector(f, parts.firstPart);
    detail::writeVector(f, importance);
    std::fclose(f);
}

struct OpacitySystemFile {
    FragmentLists lists;
    OpacityParts parts;  // firstPart and partsPerLine only (no vertices)
    std::vector<double> importance;
};

inline OpacitySystemFile loadOpacitySystem(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw std::runtime_error("cannot read " + path);
    OpacitySystemFile s;
    std::int32_t header[2] = {0, 0};
    if (std::fread(header, sizeof header, 1, f) != 1) throw std::runtime_error("opacity system file: truncated");
    s.lists.width = header[0];
    s.parts.partsPerLine = header[1];
    s.lists.offsets = detail::readVector<std::uint64_t>(f);
    s.lists.fragments = detail::readVector<LineFragmentW>(f);
    s.parts.firstPart = detail::readVector<std::uint32_t>(f);
    s.importance = detail::readVector<double>(f);
    std::fclose(f);
    return s;
}

}  // namespace tc::bench
