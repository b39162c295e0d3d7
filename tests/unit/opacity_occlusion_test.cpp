// Algorithm 1 of Günther, Rössl & Theisel 2013 (core/occlusion_matrix.h): a hand-built image of
// two crossing lines, and the parallel fast path against the reference loop.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <tuple>

#include "core/occlusion_matrix.h"

namespace tc {
namespace {

// A 16 x 16 image: line A (2 parts, global 0-1, depth 1) runs along x over rows [y0, y0 + rows),
// local w = x / 15; line B (2 parts, global 2-3, depth 2) runs along y over columns 6-9, local
// w = y / 15. They cross in rows x 4 pixels, A in front.
FragmentLists crossingLines(int y0, int rows) {
    FragmentLists lists;
    lists.offsets.clear();
    lists.offsets.push_back(0);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            // Pushed back to front on purpose: sortByDepth must order them.
            if (x >= 6 && x <= 9) {
                float w = float(y) / 15.0f;
                lists.fragments.push_back({2.0f, 2u + std::uint32_t(w), w - std::floor(w)});
            }
            if (y >= y0 && y < y0 + rows) {
                float w = float(x) / 15.0f;
                lists.fragments.push_back({1.0f, std::uint32_t(w), w - std::floor(w)});
            }
            lists.offsets.push_back(lists.fragments.size());
        }
    lists.sortByDepth();
    return lists;
}

// The fast path sums in another order than the reference and rounds each h_ij to float once:
// same pattern, and every entry within float rounding (relative 2^-24) of the reference's double.
void expectSameEntriesToFloatRounding(const SparseMatrixD& ref, const SparseMatrixF& fast) {
    ASSERT_EQ(ref.rows(), fast.rows());
    ASSERT_EQ(ref.nonZeros(), fast.nonZeros());
    for (Eigen::Index i = 0; i < ref.rows(); ++i) {
        SparseMatrixD::InnerIterator a(ref, i);
        SparseMatrixF::InnerIterator b(fast, i);
        for (; a && b; ++a, ++b) {
            ASSERT_EQ(a.index(), b.index()) << "row " << i;
            ASSERT_LE(std::abs(double(b.value()) - a.value()), std::ldexp(a.value(), -24) + 1e-12)
                << "h(" << i << ", " << a.index() << ")";
        }
        ASSERT_FALSE(a || b) << "row " << i;
    }
}

TEST(OpacityOcclusion, crossing_lines_give_the_expected_pattern_and_magnitudes) {
    FragmentLists lists = crossingLines(2, 2);
    const SparseMatrixF h = occlusionMatrix(lists, 4);
    Eigen::MatrixXd d(h.cast<double>());
    // Only A's parts (rows 0, 1) occlude only B's parts (columns 2, 3).
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (i < 2 && j >= 2)
                EXPECT_GT(d(i, j), 0.0) << i << "," << j;
            else
                EXPECT_EQ(d(i, j), 0.0) << i << "," << j;
    // Part counts of B: 4 columns x sum over y of (1 - y/15) = 32, and the same for y/15.
    std::vector<double> counts = partFragmentCounts(lists, 4);
    EXPECT_NEAR(counts[2], 32.0, 1e-4);
    EXPECT_NEAR(counts[3], 32.0, 1e-4);
    // Columns 6, 7 have round(x/15) = 0, columns 8, 9 have 1: each A part covers 2 x 2 pixels of B,
    // weighted (1 - frac, frac) with frac = y/15 for y = 2, 3.
    const double toPart2 = 2 * ((1 - 2 / 15.0) + (1 - 3 / 15.0)), toPart3 = 2 * (2 / 15.0 + 3 / 15.0);
    for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(d(i, 2), toPart2 / 32.0, 1e-6);
        EXPECT_NEAR(d(i, 3), toPart3 / 32.0, 1e-6);
        // Weights per covered pixel sum to one: count-weighted row sums are covered pixels.
        EXPECT_NEAR(d(i, 2) * counts[2] + d(i, 3) * counts[3], 4.0, 1e-5);
    }
    // Twice as many covered rows, twice the penalty.
    Eigen::MatrixXd d2(occlusionMatrix(crossingLines(2, 4), 4).cast<double>());
    const double covered2 = d2(0, 2) * counts[2] + d2(0, 3) * counts[3];
    EXPECT_NEAR(covered2, 8.0, 1e-5);
}

TEST(OpacityOcclusion, fast_path_matches_the_reference_loop) {
    std::mt19937 rng(42);
    const int pixels = 48 * 48, lines = 40, m = 5;
    std::uniform_int_distribution<int> depthCount(0, 12), line(0, lines - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    FragmentLists lists;
    lists.offsets.assign(1, 0);
    for (int p = 0; p < pixels; ++p) {
        int count = depthCount(rng);
        for (int k = 0; k < count; ++k) {
            float w = u(rng) * float(m - 1);
            std::uint32_t part = std::min(std::uint32_t(w), std::uint32_t(m - 1));
            float frac = part == std::uint32_t(m - 1) ? 0.0f : w - float(part);
            lists.fragments.push_back({u(rng), std::uint32_t(line(rng) * m) + part, frac});
        }
        lists.offsets.push_back(lists.fragments.size());
    }
    lists.sortByDepth();
    for (std::size_t p = 0; p < lists.pixelCount(); ++p)
        for (auto k = lists.offsets[p] + 1; k < lists.offsets[p + 1]; ++k)
            ASSERT_LE(lists.fragments[k - 1].depth, lists.fragments[k].depth);
    SparseMatrixD ref = occlusionMatrixReference(lists, lines * m);
    const SparseMatrixF fast = occlusionMatrix(lists, lines * m);
    ASSERT_GT(ref.nonZeros(), 1000);
    expectSameEntriesToFloatRounding(ref, fast);
    const double maxValue = Eigen::MatrixXd(ref).maxCoeff();
    EXPECT_LE(maxValue, 1.0);
    const Eigen::MatrixXd dense(ref);
    for (int i = 0; i < lines * m; ++i) EXPECT_EQ(dense(i, i), 0.0);
}

// Random sorted lists over `lines` lines of `m` parts, `maxDepth` fragments per pixel at most;
// with deepEvery > 0, pixels 5, 5 + deepEvery, ... hold `deepCount` fragments instead.
FragmentLists randomLists(int width, int height, int lines, int m, int maxDepth, unsigned seed, int deepEvery = 0,
                          int deepCount = 0) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> depthCount(0, maxDepth), line(0, lines - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    FragmentLists lists;
    lists.width = width;
    lists.offsets.assign(1, 0);
    for (int p = 0; p < width * height; ++p) {
        const int count = deepEvery > 0 && p % deepEvery == 5 ? deepCount : depthCount(rng);
        for (int k = 0; k < count; ++k) {
            const float w = u(rng) * float(m - 1);
            const std::uint32_t part = std::min(std::uint32_t(w), std::uint32_t(m - 1));
            const float frac = part == std::uint32_t(m - 1) ? 0.0f : w - float(part);
            lists.fragments.push_back({u(rng), std::uint32_t(line(rng) * m) + part, frac});
        }
        lists.offsets.push_back(lists.fragments.size());
    }
    lists.sortByDepth();
    return lists;
}

TEST(OpacityOcclusion, fast_path_matches_the_reference_with_many_parts_per_tile_and_very_deep_lists) {
    // 700 lines x 4 parts over a 80 x 40 image: tiles see more parts than their local matrix
    // holds (flushes mid-tile), and a few pixels hold lists deeper than that (direct records).
    const int lines = 700, m = 4;
    const FragmentLists lists = randomLists(80, 40, lines, m, 30, 9, 997, 400);
    const SparseMatrixD ref = occlusionMatrixReference(lists, lines * m);
    const SparseMatrixF fast = occlusionMatrix(lists, lines * m);
    ASSERT_GT(ref.nonZeros(), 100000);
    expectSameEntriesToFloatRounding(ref, fast);
}

bool sameBits(const SparseMatrixF& a, const SparseMatrixF& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() && a.nonZeros() == b.nonZeros() && a.isCompressed() &&
           b.isCompressed() && std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.rows() + 1, b.outerIndexPtr()) &&
           std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr()) &&
           std::memcmp(a.valuePtr(), b.valuePtr(), sizeof(float) * std::size_t(a.nonZeros())) == 0;
}

TEST(OpacityOcclusion, assembler_reusing_its_buffers_and_the_previous_h_gives_the_fresh_matrix_bit_for_bit) {
    // The renderer's frames: one assembler, each frame's H assembled into the last frame's arrays.
    // Frames of different depth (more and fewer non-zeros than before) and a change of the part
    // count must all give exactly what a fresh occlusionMatrix gives.
    OcclusionAssembler assembler;
    SparseMatrixF h;
    const float* firstValues = nullptr;
    struct Frame {
        int lines, maxDepth;
        unsigned seed;
    };
    for (const Frame f : {Frame{300, 12, 1}, Frame{300, 6, 2}, Frame{300, 12, 3}, Frame{120, 20, 4}}) {
        const FragmentLists lists = randomLists(64, 48, f.lines, 4, f.maxDepth, f.seed);
        const std::size_t n = std::size_t(f.lines) * 4;
        assembler.assemble(lists, n, h);
        const SparseMatrixF fresh = occlusionMatrix(lists, n);
        ASSERT_GT(fresh.nonZeros(), 1000) << f.seed;
        EXPECT_TRUE(sameBits(h, fresh)) << "frame " << f.seed;
        if (!firstValues) firstValues = h.valuePtr();
        if (f.seed == 2) {
            EXPECT_EQ(h.valuePtr(), firstValues) << "fewer non-zeros: H's arrays are refilled";
        }
    }
    assembler.release();
    const FragmentLists lists = randomLists(64, 48, 300, 4, 12, 5);
    assembler.assemble(lists, 1200, h);
    EXPECT_TRUE(sameBits(h, occlusionMatrix(lists, 1200)));
}

TEST(OpacityOcclusion, subsampled_lists_are_the_lists_of_the_pixels_containing_the_small_pixel_centres) {
    FragmentLists lists = crossingLines(2, 8);
    lists.width = 16;
    const FragmentLists same = subsampleLists(lists, 16, 1.0);
    EXPECT_EQ(same.width, 16);
    EXPECT_EQ(same.offsets, lists.offsets);
    ASSERT_EQ(same.fragments.size(), lists.fragments.size());
    for (std::size_t k = 0; k < lists.fragments.size(); ++k) {
        EXPECT_EQ(same.fragments[k].part, lists.fragments[k].part);
        EXPECT_EQ(same.fragments[k].frac, lists.fragments[k].frac);
        EXPECT_EQ(same.fragments[k].depth, lists.fragments[k].depth);
    }
    // Scale 0.5: pixel (X, Y) of the 8 x 8 image is pixel (2X + 1, 2Y + 1); 0.3: a 4 x 4 image
    // of pixels 1, 5, 8, 11 (floor((X + 0.5) / 0.3)) in each direction.
    for (const auto& [scale, size, picks] :
         {std::tuple<double, int, std::vector<int>>{0.5, 8, {1, 3, 5, 7, 9, 11, 13, 15}}, {0.3, 4, {1, 5, 8, 11}}}) {
        const FragmentLists small = subsampleLists(lists, 16, scale);
        ASSERT_EQ(small.width, size);
        ASSERT_EQ(small.pixelCount(), std::size_t(size * size));
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const std::size_t p = std::size_t(y * size + x), q = std::size_t(picks[y] * 16 + picks[x]);
                ASSERT_EQ(small.offsets[p + 1] - small.offsets[p], lists.offsets[q + 1] - lists.offsets[q]);
                for (std::uint64_t k = 0; k < small.offsets[p + 1] - small.offsets[p]; ++k) {
                    EXPECT_EQ(small.fragments[small.offsets[p] + k].part, lists.fragments[lists.offsets[q] + k].part);
                    EXPECT_EQ(small.fragments[small.offsets[p] + k].depth, lists.fragments[lists.offsets[q] + k].depth);
                }
            }
    }
    // A scale below one pixel still keeps one.
    EXPECT_EQ(subsampleLists(lists, 16, 0.01).pixelCount(), 1u);
}

TEST(OpacityOcclusion, occlusion_at_half_resolution_keeps_the_pattern_and_the_fractions_of_covered_pixels) {
    // h_ij is normalised by part j's fragment count, so halving the resolution in x and y keeps
    // it where both lines span whole pairs of pixels: A over rows 2-9, B over columns 6-9.
    FragmentLists lists = crossingLines(2, 8);
    lists.width = 16;
    const Eigen::MatrixXd full(occlusionMatrix(lists, 4).cast<double>());
    const Eigen::MatrixXd half(occlusionMatrix(subsampleLists(lists, 16, 0.5), 4).cast<double>());
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            EXPECT_EQ(full(i, j) > 0, half(i, j) > 0) << i << ", " << j;
            EXPECT_NEAR(half(i, j), full(i, j), 0.05 * full(i, j) + 1e-12) << i << ", " << j;
        }
    EXPECT_GT(full(0, 2) + full(0, 3) + full(1, 2) + full(1, 3), 0.1);
}

}  // namespace
}  // namespace tc
