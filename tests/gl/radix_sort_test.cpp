// The GPU radix sort is exact: for every input it returns what std::stable_sort by key returns
// (values follow their keys; stability makes the result unique). The GPU key pass equals the CPU
// key of core/sort_keys.h bit for bit.
#include "gl/radix_sort.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <glm/glm.hpp>
#include <numeric>
#include <random>
#include <vector>

#include "core/sort_keys.h"
#include "gl/gl_api.h"
#include "gl/objects.h"
#include "gl/sort_keys.h"
#include "gl_fixture.h"

namespace tc::test {
namespace {

using Keys = std::vector<std::uint32_t>;

struct Pairs {
    Keys keys, values;
};

Pairs referenceSort(const Keys& keys, const Keys& values) {
    std::vector<std::uint32_t> order(keys.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    Pairs out;
    out.keys.reserve(keys.size());
    out.values.reserve(keys.size());
    for (std::uint32_t i : order) {
        out.keys.push_back(keys[i]);
        out.values.push_back(values[i]);
    }
    return out;
}

Keys download(const gl::Buffer& buffer, std::size_t count) {
    Keys out(count, 0xDEADBEEFu);
    if (count) glGetNamedBufferSubData(buffer.id(), 0, count * sizeof(std::uint32_t), out.data());
    return out;
}

Pairs gpuSort(gl::RadixSort& sort, const Keys& keys, const Keys& values) {
    gl::Buffer keyBuffer = gl::makeBuffer(keys.size() * 4, keys.data());
    gl::Buffer valueBuffer = gl::makeBuffer(values.size() * 4, values.data());
    sort.sort(keyBuffer, valueBuffer, keys.size());
    return {download(keyBuffer, keys.size()), download(valueBuffer, keys.size())};
}

Keys iota(std::size_t n) {
    Keys v(n);
    std::iota(v.begin(), v.end(), 0u);
    return v;
}

Keys randomKeys(std::size_t n, std::uint32_t seed, std::uint32_t mask = 0xFFFFFFFFu) {
    std::mt19937 rng(seed);
    Keys v(n);
    for (auto& k : v) k = rng() & mask;
    return v;
}

// Compares the first mismatch only: a 10^6-entry EXPECT_EQ on vectors prints megabytes.
::testing::AssertionResult sameAsStableSort(gl::RadixSort& sort, const Keys& keys, const Keys& values) {
    Pairs expected = referenceSort(keys, values);
    Pairs actual = gpuSort(sort, keys, values);
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (actual.keys[i] != expected.keys[i] || actual.values[i] != expected.values[i])
            return ::testing::AssertionFailure()
                   << "n = " << keys.size() << ": first mismatch at " << i << ": got (" << actual.keys[i] << ", "
                   << actual.values[i] << "), expected (" << expected.keys[i] << ", " << expected.values[i] << ")";
    return ::testing::AssertionSuccess();
}

class RadixSortTest : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        if (!HasFatalFailure()) m_sort = std::make_unique<gl::RadixSort>(gl::RadixSort::create());
    }
    gl::RadixSort& sorter() { return *m_sort; }
    std::unique_ptr<gl::RadixSort> m_sort;
};

TEST_F(RadixSortTest, empty_and_single_element_inputs_are_left_as_they_are) {
    gl::Buffer keys = gl::makeBuffer(0), values = gl::makeBuffer(0);
    sorter().sort(keys, values, 0);
    Keys one = {42u}, oneValue = {7u};
    Pairs sorted = gpuSort(sorter(), one, oneValue);
    EXPECT_EQ(sorted.keys, one);
    EXPECT_EQ(sorted.values, oneValue);
}

TEST_F(RadixSortTest, random_keys_match_stable_sort_at_tile_and_block_boundaries) {
    // 4096 = one tile (16 lanes x 256); 65537 and 10^6 need a two-level histogram scan.
    for (std::size_t n : {2u, 255u, 256u, 257u, 1000u, 4095u, 4096u, 4097u, 65537u, 1000000u})
        EXPECT_TRUE(sameAsStableSort(sorter(), randomKeys(n, static_cast<std::uint32_t>(n)), iota(n)));
}

TEST_F(RadixSortTest, one_scratch_serves_shrinking_and_growing_inputs) {
    for (std::size_t n : {100000u, 10u, 300000u, 257u})
        EXPECT_TRUE(sameAsStableSort(sorter(), randomKeys(n, 3), randomKeys(n, 4)));
}

TEST_F(RadixSortTest, duplicate_heavy_keys_keep_their_input_order) {
    const std::size_t n = 200000;
    EXPECT_TRUE(sameAsStableSort(sorter(), randomKeys(n, 5, 0xFu), iota(n)));  // 16 values
    // Few distinct keys that differ only in the top and bottom digits.
    Keys keys = randomKeys(n, 6, 0x80000001u);
    EXPECT_TRUE(sameAsStableSort(sorter(), keys, iota(n)));
    Keys all(n, 0x12345678u);
    EXPECT_TRUE(sameAsStableSort(sorter(), all, iota(n)));
}

TEST_F(RadixSortTest, sorted_reversed_and_top_bit_keys_match_stable_sort) {
    const std::size_t n = 100003;
    Keys sorted = randomKeys(n, 8);
    std::sort(sorted.begin(), sorted.end());
    EXPECT_TRUE(sameAsStableSort(sorter(), sorted, iota(n)));
    Keys reversed(sorted.rbegin(), sorted.rend());
    EXPECT_TRUE(sameAsStableSort(sorter(), reversed, iota(n)));
    Keys top = randomKeys(n, 9);
    for (std::size_t i = 0; i < n; ++i)
        if (i % 3 == 0) top[i] |= 0x80000000u;
    top[0] = 0xFFFFFFFFu;
    top[1] = 0u;
    top[2] = 0x80000000u;
    top[3] = 0x7FFFFFFFu;
    EXPECT_TRUE(sameAsStableSort(sorter(), top, iota(n)));
}

TEST_F(RadixSortTest, float_keys_of_both_signs_sort_in_float_order) {
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> value(-100.0f, 100.0f);
    const std::size_t n = 50000;
    Keys keys(n);
    for (auto& k : keys) k = sortKeyFromFloat(value(rng));
    Pairs sorted = gpuSort(sorter(), keys, iota(n));
    for (std::size_t i = 1; i < n; ++i)
        ASSERT_LE(floatFromSortKey(sorted.keys[i - 1]), floatFromSortKey(sorted.keys[i])) << i;
}

TEST_F(RadixSortTest, four_bit_digits_sort_the_same_as_eight_bit_digits) {
    gl::RadixSort sort4 = gl::RadixSort::create({.digitBits = 4, .lanes = 64, .itemsPerLane = 64});
    EXPECT_TRUE(sameAsStableSort(sort4, randomKeys(300001, 13), iota(300001)));
    EXPECT_TRUE(sameAsStableSort(sort4, randomKeys(70000, 14, 0xF000000Fu), iota(70000)));
}

TEST_F(RadixSortTest, a_lowest_bit_sorts_stably_by_the_high_key_bits_only) {
    // The approximate order of opaque culling (gl/segment_order.cpp): stable by key >> 16, so the
    // low bits keep their input order within a bucket; that differs from a full sort here.
    const std::size_t n = 70000;
    Keys keys = randomKeys(n, 9, 0x00FFFFFFu), values = iota(n);
    Keys high(n);
    for (std::size_t i = 0; i < n; ++i) high[i] = keys[i] >> 16;
    Pairs expected = referenceSort(high, values);
    gl::Buffer keyBuffer = gl::makeBuffer(n * 4, keys.data());
    gl::Buffer valueBuffer = gl::makeBuffer(n * 4, values.data());
    sorter().sort(keyBuffer, valueBuffer, n, 16);
    Keys sortedKeys = download(keyBuffer, n), sortedValues = download(valueBuffer, n);
    EXPECT_EQ(sortedValues, expected.values);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(sortedKeys[i], keys[sortedValues[i]]) << i;
    EXPECT_FALSE(std::is_sorted(sortedKeys.begin(), sortedKeys.end()));
}

TEST_F(RadixSortTest, ten_million_random_keys_match_stable_sort) {
    const std::size_t n = 10000000;
    auto start = std::chrono::steady_clock::now();
    EXPECT_TRUE(sameAsStableSort(sorter(), randomKeys(n, 15), iota(n)));
    std::printf("10^7 keys: GPU sort + reference + transfers %.0f ms\n",
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

// 20k random segments around a camera: the GPU key pass equals core's segmentSortKey bit for bit
// (both compute the same IEEE operations in the same order, the shader with `precise` so no FMA
// is contracted), and sorting those keys gives the CPU's front-to-back order.
TEST_F(RadixSortTest, scene_keys_equal_cpu_keys_bit_for_bit_and_sort_front_to_back) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> coord(-3.0f, 3.0f), step(-0.2f, 0.2f);
    const std::size_t segments = 20000;
    std::vector<glm::vec4> positions;
    Keys segmentVertices;
    for (std::size_t s = 0; s < segments; ++s) {
        glm::vec3 a(coord(rng), coord(rng), coord(rng));
        glm::vec3 b = s % 97 == 0 ? a : a + glm::vec3(step(rng), step(rng), step(rng));
        // Shuffled vertex order: keys must follow segmentVertices, not the vertex index.
        positions.emplace_back(b, 0.01f);
        positions.emplace_back(a, 0.01f);
        segmentVertices.push_back(static_cast<std::uint32_t>(2 * s + 1));
        segmentVertices.push_back(static_cast<std::uint32_t>(2 * s));
    }
    gl::Buffer positionBuffer = gl::makeBuffer(positions.size() * 16, positions.data());
    gl::Buffer segmentBuffer = gl::makeBuffer(segmentVertices.size() * 4, segmentVertices.data());
    gl::SegmentSortKeys keyPass = gl::SegmentSortKeys::create();

    const glm::vec3 eye(0.3f, -0.7f, 1.1f);  // inside the cloud: distances near 0 and far
    const glm::vec3 forward = glm::normalize(glm::vec3(0.2f, 0.5f, -1.0f));
    for (bool orthographic : {false, true}) {
        SCOPED_TRACE(orthographic ? "orthographic" : "perspective");
        gl::Buffer keys, ids;
        keyPass.compute(positionBuffer, segmentBuffer, segments, eye, orthographic, forward, keys, ids);
        Keys gpuKeys = download(keys, segments);
        Keys cpuKeys(segments);
        std::size_t mismatches = 0;
        for (std::size_t s = 0; s < segments; ++s) {
            glm::vec3 x0 = positions[segmentVertices[2 * s]];
            glm::vec3 x1 = positions[segmentVertices[2 * s + 1]];
            cpuKeys[s] = segmentSortKey(eye, orthographic, forward, x0, x1);
            if (gpuKeys[s] != cpuKeys[s] && mismatches++ < 5)
                ADD_FAILURE() << "segment " << s << ": GPU " << floatFromSortKey(gpuKeys[s]) << " CPU "
                              << floatFromSortKey(cpuKeys[s]);
        }
        EXPECT_EQ(mismatches, 0u);
        EXPECT_EQ(download(ids, segments), iota(segments));
        if (orthographic) {  // the eye is inside the cloud: some segments are behind it
            EXPECT_TRUE(
                std::any_of(cpuKeys.begin(), cpuKeys.end(), [](std::uint32_t k) { return floatFromSortKey(k) < 0; }));
        }

        sorter().sort(keys, ids, segments);
        Pairs expected = referenceSort(cpuKeys, iota(segments));
        EXPECT_EQ(download(keys, segments), expected.keys);
        EXPECT_EQ(download(ids, segments), expected.values);
    }
}

}  // namespace
}  // namespace tc::test
