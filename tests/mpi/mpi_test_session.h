#pragma once
// The MpiSession of tubecast_mpi_tests (made in mpi_test_main.cpp) and deterministic per-rank test
// data that any rank can regenerate for any other rank.
#include <cstdint>
#include <cstring>

#include "cli/mpi_session.h"

namespace tc::test {

cli::MpiSession& mpi();

// A hash of (a, b, c) to 64 bits (splitmix64's finaliser over a combination of the inputs).
inline std::uint64_t hash3(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
    std::uint64_t x = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull ^
                      (c + 0x85157AF5ull) * 0x94D049BB133111EBull;
    x ^= x >> 30;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 27;
    x *= 0x94D049BB133111EBull;
    x ^= x >> 31;
    return x;
}

// Uniform in [0, 1) from hash3.
inline float unit(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
    return float(hash3(a, b, c) >> 40) * 0x1p-24f;
}

inline std::uint32_t bitsOf(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

}  // namespace tc::test
