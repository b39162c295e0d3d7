#pragma once
// 8-bit sRGB encoding of linear values by table: the output path converts every pixel of every
// frame (2M pixels x 3 channels at 1920x1080), and three powf per pixel cost more than zlib's
// fastest level (docs/performance.md, "Design notes"). The table is built from linearToSrgb
// itself (core/color.h), so the result is bit-identical to the formula it replaces.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace tc {

// The table behind linearToSrgb8, for loops over whole images: get it once (srgb8Encoder()) and
// encode inline, without a call and a static-initialisation check per channel.
class Srgb8Encoder {
public:
    // lround(255 * linearToSrgb(clamp(v, 0, 1))); NaN encodes as 0.
    std::uint8_t operator()(float v) const {
        v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
        unsigned k = m_start[std::size_t(v * float(kBuckets))];
        while (v >= m_lower[k + 1]) ++k;
        return std::uint8_t(k);
    }

private:
    friend const Srgb8Encoder& srgb8Encoder();
    Srgb8Encoder();
    // The code is a non-decreasing function of v, so it is fixed by the 255 values where it steps
    // up: m_lower[k] = the smallest float v in [0, 1] whose code is >= k. m_start[i] is the code
    // of i / kBuckets, a lower bound for every v in bucket i; from there at most a few thresholds
    // are passed.
    static constexpr int kBuckets = 4096;
    std::array<float, 257> m_lower{};
    std::array<std::uint8_t, kBuckets + 1> m_start{};
};
const Srgb8Encoder& srgb8Encoder();

// lround(255 * linearToSrgb(clamp(v, 0, 1))); NaN encodes as 0.
inline std::uint8_t linearToSrgb8(float v) {
    return srgb8Encoder()(v);
}

// The same, by evaluating the formula (the definition; for tests).
std::uint8_t linearToSrgb8Direct(float v);

}  // namespace tc
