// Visibility-sort keys: the float -> uint32 map preserves order for every sign and magnitude and
// inverts exactly; the segment distances match their analytic values.
#include "core/sort_keys.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace tc {
namespace {

TEST(SortKeys, key_order_equals_float_order_across_signs_zeros_denormals_and_infinities) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    constexpr float maxF = std::numeric_limits<float>::max();
    constexpr float minNormal = std::numeric_limits<float>::min();
    constexpr float denorm = std::numeric_limits<float>::denorm_min();
    const std::vector<float> ascending = {-inf,      -maxF,  -1e10f, -1.0f, -minNormal,   -denorm, -0.0f, 0.0f, denorm,
                                          minNormal, 1e-30f, 0.5f,   1.0f,  1.0f + 1e-7f, 3.0f,    1e30f, maxF, inf};
    for (std::size_t i = 1; i < ascending.size(); ++i)
        EXPECT_LT(sortKeyFromFloat(ascending[i - 1]), sortKeyFromFloat(ascending[i]))
            << ascending[i - 1] << " vs " << ascending[i];
}

TEST(SortKeys, random_float_pairs_compare_like_their_keys) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::uint32_t> bits;
    for (int i = 0; i < 200000; ++i) {
        float a = std::bit_cast<float>(bits(rng)), b = std::bit_cast<float>(bits(rng));
        if (std::isnan(a) || std::isnan(b)) continue;
        if (a == b) continue;  // only +0 == -0; ordered -0 < +0 above
        EXPECT_EQ(a < b, sortKeyFromFloat(a) < sortKeyFromFloat(b)) << a << " vs " << b;
    }
}

TEST(SortKeys, non_negative_floats_keep_their_bits_below_the_top_bit) {
    EXPECT_EQ(sortKeyFromFloat(0.0f), 0x80000000u);
    EXPECT_EQ(sortKeyFromFloat(1.0f), 0x3F800000u | 0x80000000u);
    EXPECT_EQ(sortKeyFromFloat(-1.0f), ~0xBF800000u);
    EXPECT_EQ(sortKeyFromFloat(-0.0f), 0x7FFFFFFFu);
}

TEST(SortKeys, float_from_sort_key_inverts_every_bit_pattern) {
    std::mt19937 rng(11);
    std::uniform_int_distribution<std::uint32_t> bits;
    for (int i = 0; i < 100000; ++i) {
        std::uint32_t b = bits(rng);
        EXPECT_EQ(std::bit_cast<std::uint32_t>(floatFromSortKey(sortKeyFromFloat(b))), b);
        EXPECT_EQ(sortKeyFromFloat(std::bit_cast<std::uint32_t>(floatFromSortKey(b))), b);
    }
}

TEST(SortKeys, segment_distance_is_the_distance_to_the_closest_point_of_the_segment) {
    const glm::vec3 a(-1, 0, 0), b(1, 0, 0);
    EXPECT_FLOAT_EQ(segmentDistance({0, 2, 0}, a, b), 2.0f);                     // interior
    EXPECT_FLOAT_EQ(segmentDistance({0.5f, 0, -3}, a, b), 3.0f);                 // interior, other side
    EXPECT_FLOAT_EQ(segmentDistance({4, 4, 0}, a, b), 5.0f);                     // clamped to b (3-4-5)
    EXPECT_FLOAT_EQ(segmentDistance({-4, 0, 4}, a, b), 5.0f);                    // clamped to a
    EXPECT_FLOAT_EQ(segmentDistance({0.25f, 0, 0}, a, b), 0.0f);                 // on the segment
    EXPECT_FLOAT_EQ(segmentDistance({0, 3, 4}, b, b), std::sqrt(1.0f + 25.0f));  // degenerate
    EXPECT_EQ(segmentDistance({0, 2, 0}, a, b), segmentDistance({0, 2, 0}, b, a));
}

TEST(SortKeys, orthographic_depth_is_the_nearer_end_point_along_forward_and_may_be_negative) {
    const glm::vec3 eye(0, 0, 5), forward(0, 0, -1);
    EXPECT_FLOAT_EQ(segmentDepth(eye, forward, {0, 0, 0}, {10, 3, 2}), 3.0f);
    EXPECT_FLOAT_EQ(segmentDepth(eye, forward, {0, 0, 7}, {1, 1, 0}), -2.0f);  // behind the eye
    EXPECT_EQ(segmentSortKey(eye, true, forward, {0, 0, 7}, {1, 1, 0}), sortKeyFromFloat(-2.0f));
    EXPECT_LT(segmentSortKey(eye, true, forward, {0, 0, 7}, {1, 1, 0}),
              segmentSortKey(eye, true, forward, {0, 0, 0}, {0, 0, 0}));
    EXPECT_EQ(segmentSortKey(eye, false, forward, {0, 0, 1}, {0, 0, 0}), sortKeyFromFloat(4.0f));
}

}  // namespace
}  // namespace tc
