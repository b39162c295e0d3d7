#pragma once
// Stable LSD radix sort of (uint32 key, uint32 value) pairs in GL compute shaders — the GPU
// visibility sort of Groß & Gumhold 2020, Sect. 4.1 (keys: core/sort_keys.h, values: segment ids).
//
// Each pass sorts by one digit of RADIX_BITS bits, lowest digit first, in three steps:
//   1. histogram  (shaders/radix_sort_histogram.comp): digit counts per workgroup tile, stored
//                 digit-major, histograms[digit * groups + group];
//   2. scan       (shaders/radix_sort_scan.comp): multi-level exclusive scan of that array, so
//                 entry (digit, group) becomes the first output position of the tile's keys of
//                 that digit;
//   3. scatter    (shaders/radix_sort_scatter.comp): stable; every lane walks a contiguous run of
//                 the tile in order with per-lane, per-digit positions in shared memory (no
//                 subgroup operations, no atomics).
// Passes ping-pong between the caller's buffers and internal scratch buffers; the pass count
// (32 / digitBits) is even, so the sorted result ends in the caller's buffers.
#include <cstddef>
#include <vector>

#include "gl/objects.h"

namespace tc::gl {

class RadixSort {
public:
    struct Config {
        // Digit width, 4 (8 passes) or 8 (4 passes). 8 is faster on llvmpipe (see
        // docs/performance.md: fewer passes over memory beat the larger histogram and scan).
        int digitBits = 8;
        // Invocations per workgroup of histogram and scatter, and keys per lane (tile = lanes *
        // itemsPerLane). 16 x 256 measured fastest on llvmpipe (8 x 512: +15 %, 32 x 128: +95 %).
        int lanes = 16;
        int itemsPerLane = 256;
    };

    // Compiles the programs. Needs a current context; throws tc::Error(Internal) on a compile
    // failure or an invalid config (digitBits not 4 or 8, shared memory over the GL limit).
    static RadixSort create(const Config& config);
    static RadixSort create() { return create(Config{}); }

    // Sorts the first `count` uint32 entries of `keys` ascending, moving the uint32 entries of
    // `values` with them; equal keys keep their input order (stable). Both buffers must hold at
    // least count * 4 bytes (checked). Scratch memory (2 x count x 4 bytes plus histograms) is
    // owned by this object and grown as needed, never shrunk.
    // GL state: binds shader storage buffer binding points 0..4 and leaves no program bound.
    // Ends with glMemoryBarrier(shader storage | buffer update | element array | vertex attrib |
    // command), so shaders, draws and glGetNamedBufferSubData see the result.
    // lowestBit > 0 sorts by key >> lowestBit only (stable, so ties keep their input order), with
    // (32 - lowestBit) / digitBits passes instead of 32 / digitBits: an approximate order for
    // callers that only need one (opaque culling, gl/segment_order.h). lowestBit must be a
    // multiple of 2 * digitBits (an even pass count keeps the result in the caller's buffers).
    void sort(const Buffer& keys, const Buffer& values, std::size_t count, int lowestBit = 0);

    const Config& config() const { return m_config; }

private:
    struct ScanLevel {
        Buffer sums;  // one per block of the level above
        std::size_t count = 0;
    };

    RadixSort() = default;
    void ensureScratch(std::size_t count);
    void scan(GLuint data, std::size_t count, std::size_t level);

    Config m_config;
    Program m_histogram, m_scatter, m_scanReduce, m_scan;
    Buffer m_keysScratch, m_valuesScratch, m_histograms;
    std::size_t m_scratchCapacity = 0, m_histogramCapacity = 0;
    std::vector<ScanLevel> m_scanLevels;
};

}  // namespace tc::gl
