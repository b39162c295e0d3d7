// Products with H straight from the fragment lists (core/fragment_occlusion.h) against H
// assembled by the reference loop of Algorithm 1 (core/occlusion_matrix.h, without the clamp),
// and the opacity energy and its solve built either way.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <memory>
#include <random>

#include "core/fragment_occlusion.h"
#include "core/occlusion_matrix.h"
#include "core/opacity_optimization.h"

namespace tc {
namespace {

// Random sorted lists over `lines` polylines of `m` parts. Every fourth fragment gets a twin of
// the same part just behind it (the joint of two segments of one part), so the pairs of a part
// with itself, which Algorithm 1 skips, occur often; some lists are deep.
FragmentLists randomLists(int width, int height, int lines, int m, int maxDepth, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> depthCount(0, maxDepth), line(0, lines - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    FragmentLists lists;
    lists.width = width;
    lists.offsets.assign(1, 0);
    for (int p = 0; p < width * height; ++p) {
        const int count = p % 331 == 7 ? 6 * maxDepth : depthCount(rng);
        for (int k = 0; k < count; ++k) {
            const float w = u(rng) * float(m - 1);
            const std::uint32_t part = std::min(std::uint32_t(w), std::uint32_t(m - 1));
            const float frac = part == std::uint32_t(m - 1) ? 0.0f : w - float(part);
            const std::uint32_t global = std::uint32_t(line(rng) * m) + part;
            const float depth = u(rng);
            lists.fragments.push_back({depth, global, frac});
            if (k % 4 == 0)
                lists.fragments.push_back({depth + 1e-3f, global, std::min(frac + 0.05f, frac > 0 ? 0.99f : 0.0f)});
        }
        lists.offsets.push_back(lists.fragments.size());
    }
    lists.sortByDepth();
    return lists;
}

Eigen::VectorXd randomVector(Eigen::Index n, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd v(n);
    for (Eigen::Index i = 0; i < n; ++i) v[i] = u(rng);
    return v;
}

TEST(OpacityFragmentOcclusion, products_equal_the_reference_matrix_without_clamp) {
    const int lines = 60, m = 6, n = lines * m;
    const FragmentLists lists = randomLists(40, 30, lines, m, 14, 3);
    const Eigen::MatrixXd h(occlusionMatrixReference(lists, n, false));
    ASSERT_GT((h.array() > 0).count(), 5000);
    for (int i = 0; i < n; ++i) ASSERT_EQ(h(i, i), 0.0);
    const FragmentOcclusion op(lists, n);
    std::uint64_t pairs = 0;
    for (std::size_t p = 0; p < lists.pixelCount(); ++p) {
        const std::uint64_t l = lists.offsets[p + 1] - lists.offsets[p];
        pairs += l > 1 ? l * (l - 1) / 2 : 0;
    }
    EXPECT_EQ(op.pairCount(), pairs);

    std::mt19937 rng(5);
    for (int trial = 0; trial < 3; ++trial) {
        const Eigen::VectorXd x = randomVector(n, rng), y = randomVector(n, rng);
        Eigen::VectorXd hx, hty;
        op.multiply(&x, &hx, &y, &hty);
        const Eigen::VectorXd refHx = h * x, refHty = h.transpose() * y;
        EXPECT_LE((hx - refHx).lpNorm<Eigen::Infinity>(), 1e-12 * std::max(1.0, refHx.lpNorm<Eigen::Infinity>()));
        EXPECT_LE((hty - refHty).lpNorm<Eigen::Infinity>(), 1e-12 * std::max(1.0, refHty.lpNorm<Eigen::Infinity>()));
        // One output alone gives the same.
        Eigen::VectorXd only;
        op.multiply(&x, &only, nullptr, nullptr);
        EXPECT_LE((only - hx).lpNorm<Eigen::Infinity>(), 1e-14 * std::max(1.0, hx.lpNorm<Eigen::Infinity>()));
        op.multiply(nullptr, nullptr, &y, &only);
        EXPECT_LE((only - hty).lpNorm<Eigen::Infinity>(), 1e-14 * std::max(1.0, hty.lpNorm<Eigen::Infinity>()));
    }
}

TEST(OpacityFragmentOcclusion, small_blocks_give_the_reference_products) {
    // The lists are cut into blocks of at most blockSlots local slots (groups of 8 parts plus the
    // next group's first) with block-local ids; tiny blocks give hundreds of them, the groups here
    // straddle polylines (6 parts each), and lists touching more groups than a block holds
    // become blocks of their own (one slot: every list). Also with an unknown image width (no Z
    // order over the image).
    const int lines = 60, m = 6, n = lines * m;
    for (int width : {40, 0}) {
        FragmentLists lists = randomLists(40, 30, lines, m, 14, 21);
        lists.width = width;
        const Eigen::MatrixXd h(occlusionMatrixReference(lists, n, false));
        std::mt19937 rng(9);
        const Eigen::VectorXd x = randomVector(n, rng), y = randomVector(n, rng);
        const Eigen::VectorXd refHx = h * x, refHty = h.transpose() * y;
        for (std::size_t blockSlots : {std::size_t(1), std::size_t(18), std::size_t(64), std::size_t(65536)}) {
            const FragmentOcclusion op(lists, n, blockSlots);
            Eigen::VectorXd hx, hty;
            op.multiply(&x, &hx, &y, &hty);
            EXPECT_LE((hx - refHx).lpNorm<Eigen::Infinity>(), 1e-12 * refHx.lpNorm<Eigen::Infinity>())
                << "width " << width << ", blockSlots " << blockSlots;
            EXPECT_LE((hty - refHty).lpNorm<Eigen::Infinity>(), 1e-12 * refHty.lpNorm<Eigen::Infinity>())
                << "width " << width << ", blockSlots " << blockSlots;
        }
    }
}

TEST(OpacityFragmentOcclusion, equals_the_clamped_fast_path_where_no_entry_reaches_one) {
    // Shallow lists without twins: no h_ij reaches 1, so the clamp of the assembled path changes
    // nothing and the two products agree with the tiled fast path too.
    std::mt19937 rng(11);
    const int lines = 30, m = 4, n = lines * m, width = 50, height = 40;
    std::uniform_int_distribution<int> depthCount(0, 5), line(0, lines - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    FragmentLists lists;
    lists.width = width;
    lists.offsets.assign(1, 0);
    for (int p = 0; p < width * height; ++p) {
        for (int k = depthCount(rng); k > 0; --k) {
            const float w = u(rng) * float(m - 1);
            const std::uint32_t part = std::min(std::uint32_t(w), std::uint32_t(m - 1));
            lists.fragments.push_back({u(rng), std::uint32_t(line(rng) * m) + part, w - float(part)});
        }
        lists.offsets.push_back(lists.fragments.size());
    }
    lists.sortByDepth();
    const SparseMatrixD clamped = occlusionMatrixReference(lists, n);
    ASSERT_LT(Eigen::MatrixXd(clamped).maxCoeff(), 1.0);
    // The tiled fast path stores each h_ij rounded to float (OpacityEnergy's form).
    const SparseMatrixD fast = occlusionMatrix(lists, n).cast<double>();
    const FragmentOcclusion op(lists, n);
    const Eigen::VectorXd x = randomVector(n, rng);
    Eigen::VectorXd hx, htx;
    op.multiply(&x, &hx, &x, &htx);
    EXPECT_LE((hx - clamped * x).lpNorm<Eigen::Infinity>(), 1e-12);
    EXPECT_LE((htx - SparseMatrixD(clamped.transpose()) * x).lpNorm<Eigen::Infinity>(), 1e-12);
    EXPECT_LE((hx - fast * x).lpNorm<Eigen::Infinity>(), 1e-6 * hx.lpNorm<Eigen::Infinity>());
    EXPECT_LE((htx - SparseMatrixD(fast.transpose()) * x).lpNorm<Eigen::Infinity>(),
              1e-6 * htx.lpNorm<Eigen::Infinity>());
}

TEST(OpacityFragmentOcclusion, energy_and_solve_match_the_assembled_energy) {
    const int lines = 60, m = 6, n = lines * m;
    const FragmentLists lists = randomLists(40, 30, lines, m, 14, 8);
    const SparseMatrixD h = occlusionMatrixReference(lists, n, false);
    OpacityParts parts;
    parts.partsPerLine = m;
    for (int l = 0; l <= lines; ++l) parts.firstPart.push_back(std::uint32_t(l * m));
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> g(n);
    for (double& v : g) v = u(rng);
    const OpacityWeights w{1.0, 4.0, 0.4, 0.3, 1.0};
    const OpacityEnergy assembled(h, g, parts, w);
    const OpacityEnergy fromLists(std::make_shared<const FragmentOcclusion>(lists, n), g, parts, w);
    EXPECT_TRUE(fromLists.fromFragments());

    // Same Q: the assembled energy stores H in single precision, so agreement is to float rounding.
    const Eigen::VectorXd a = (randomVector(n, rng).array() * 0.5 + 0.5).matrix();
    Eigen::VectorXd qa, qb;
    assembled.multiply(a, qa);
    fromLists.multiply(a, qb);
    EXPECT_LE((qa - qb).lpNorm<Eigen::Infinity>(), 1e-5 * qa.lpNorm<Eigen::Infinity>());
    EXPECT_NEAR(assembled.energy(a), fromLists.energy(a), 1e-5 * assembled.energy(a));

    // Both minimisers to 1e-9; KKT holds for the fragment energy (its preconditioner uses an
    // estimated diagonal) and the solutions agree to the float rounding of H.
    QpSolverOptions opt;
    opt.tolerance = 1e-9;
    const Eigen::VectorXd lo = Eigen::VectorXd::Zero(n), hi = Eigen::VectorXd::Ones(n);
    const QpResult ra = solveBoundedQp(assembled, assembled.linearTerm(), lo, hi, hi, opt);
    const QpResult rb = solveBoundedQp(fromLists, fromLists.linearTerm(), lo, hi, hi, opt);
    ASSERT_TRUE(ra.converged);
    ASSERT_TRUE(rb.converged) << rb.residual;
    Eigen::VectorXd gb;
    fromLists.multiply(rb.x, gb);
    gb += fromLists.linearTerm();
    EXPECT_LE(projectedGradientNorm(gb, rb.x, lo, hi), 1e-9);
    EXPECT_LT(rb.x.minCoeff(), 0.9);  // occlusion matters in this problem
    EXPECT_LE((ra.x - rb.x).lpNorm<Eigen::Infinity>(), 1e-5);
}

}  // namespace
}  // namespace tc
