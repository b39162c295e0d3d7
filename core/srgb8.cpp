#include "core/srgb8.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "core/color.h"

namespace tc {
namespace {

float clamp01(float v) {
    return std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
}

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}
float fromBits(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

// The code is a non-decreasing function of v, so it is fixed by the 255 values where it steps up:
// lower[k] = the smallest float v in [0, 1] whose code is >= k, found by bisection over the bit
// patterns (non-negative floats order like their bits). `start[i]` is the code of i / kBuckets, a
// lower bound for every v in bucket i; from there at most a few thresholds are passed.
struct Table {
    static constexpr int kBuckets = 4096;
    std::array<float, 257> lower{};
    std::array<std::uint8_t, kBuckets + 1> start{};

    Table() {
        lower[0] = 0.0f;
        for (int k = 1; k <= 255; ++k) {
            std::uint32_t lo = bits(0.0f), hi = bits(1.0f);  // code(hi) = 255 >= k
            while (lo < hi) {
                const std::uint32_t mid = lo + (hi - lo) / 2;
                if (linearToSrgb8Direct(fromBits(mid)) >= k)
                    hi = mid;
                else
                    lo = mid + 1;
            }
            lower[std::size_t(k)] = fromBits(lo);
        }
        lower[256] = 2.0f;  // above every clamped value: the search stops at 255
        for (int i = 0; i <= kBuckets; ++i) start[std::size_t(i)] = linearToSrgb8Direct(float(i) / float(kBuckets));
    }
};

const Table& table() {
    static const Table t;
    return t;
}

}  // namespace

std::uint8_t linearToSrgb8Direct(float v) {
    return std::uint8_t(std::lround(clamp01(linearToSrgb(clamp01(v))) * 255.0f));
}

std::uint8_t linearToSrgb8(float v) {
    const Table& t = table();
    v = clamp01(v);
    unsigned k = t.start[std::size_t(v * float(Table::kBuckets))];
    while (v >= t.lower[k + 1]) ++k;
    return std::uint8_t(k);
}

}  // namespace tc
