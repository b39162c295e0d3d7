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

}  // namespace

std::uint8_t linearToSrgb8Direct(float v) {
    return std::uint8_t(std::lround(clamp01(linearToSrgb(clamp01(v))) * 255.0f));
}

Srgb8Encoder::Srgb8Encoder() {
    m_lower[0] = 0.0f;
    for (int k = 1; k <= 255; ++k) {
        // Bisection over the bit patterns (non-negative floats order like their bits).
        std::uint32_t lo = bits(0.0f), hi = bits(1.0f);  // code(hi) = 255 >= k
        while (lo < hi) {
            const std::uint32_t mid = lo + (hi - lo) / 2;
            if (linearToSrgb8Direct(fromBits(mid)) >= k)
                hi = mid;
            else
                lo = mid + 1;
        }
        m_lower[std::size_t(k)] = fromBits(lo);
    }
    m_lower[256] = 2.0f;  // above every clamped value: the search stops at 255
    for (int i = 0; i <= kBuckets; ++i) m_start[std::size_t(i)] = linearToSrgb8Direct(float(i) / float(kBuckets));
}

const Srgb8Encoder& srgb8Encoder() {
    static const Srgb8Encoder encoder;
    return encoder;
}

}  // namespace tc
