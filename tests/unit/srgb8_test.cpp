// core/srgb8.h: the table encoding equals the formula it replaces (lround(255 * linearToSrgb(v))).
#include "core/srgb8.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace tc {
namespace {

float fromBits(std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

TEST(Srgb8, table_equals_the_formula_around_every_step_and_on_a_dense_sample_of_all_floats_in_0_1) {
    const std::uint32_t one = 0x3F800000u;  // bits of 1.0f
    constexpr std::uint32_t kStride = 257;
    int steps = 0;
    // Every 257th bit pattern (~4M floats over all exponents), and every pattern in the windows
    // where the code steps up (where a wrong threshold would show).
    std::uint8_t previous = linearToSrgb8Direct(0.0f);
    for (std::uint32_t u = kStride; u <= one; u += kStride) {
        const float v = fromBits(u);
        const std::uint8_t direct = linearToSrgb8Direct(v);
        ASSERT_EQ(linearToSrgb8(v), direct) << v;
        if (direct != previous) {
            ++steps;
            for (std::uint32_t w = u - kStride; w < u; ++w)
                ASSERT_EQ(linearToSrgb8(fromBits(w)), linearToSrgb8Direct(fromBits(w))) << fromBits(w);
        }
        previous = direct;
    }
    EXPECT_GE(steps, 255);  // every code is reached
    EXPECT_EQ(linearToSrgb8(0.0f), 0);
    EXPECT_EQ(linearToSrgb8(1.0f), 255);
    EXPECT_EQ(linearToSrgb8(-3.0f), 0);
    EXPECT_EQ(linearToSrgb8(7.0f), 255);
    EXPECT_EQ(linearToSrgb8(std::numeric_limits<float>::quiet_NaN()), 0);
    EXPECT_EQ(linearToSrgb8(std::numeric_limits<float>::infinity()), 255);
    EXPECT_EQ(linearToSrgb8(0.5f), 188);  // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 187.5 -> 188
}

}  // namespace
}  // namespace tc
