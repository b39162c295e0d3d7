#pragma once
// The occlusion matrix H of opacity optimization applied straight from the sorted per-pixel
// fragment lists, without assembling it (render.opacity.occlusion "fragments").
//
// Algorithm 1 (Günther, Rössl & Theisel 2013) sums, for every pixel, over the pairs (A, B) with A
// in front of B. Assembling H costs the number of such pairs (quadratic in the list length: 22 M
// pairs for 2.3 M fragments at 8k parts, and H has up to that many non-zeros), but a product
// with H only needs sums over them, and those are prefix sums along each list:
//
//   (S^T y)_j = sum over fragments B: w_j(B) * (sum of y_round(A.w) over the A in front of B)
//   (S x)_i   = sum over fragments A with round(A.w) = i:
//                   sum over the B behind A of w0(B) x_floor(B.w) + w1(B) x_floor(B.w)+1
//
// with S the unnormalised pair sum including i == j. Algorithm 1 skips i == j (a part does not
// occlude itself), which removes exactly S's diagonal d, so with N = diag(1 / fragment count)
//
//   H = (S - diag(d)) N,   H x = S (N x) - d . (N x),   H^T y = N (S^T y - d . y).
//
// d is summed once, in time linear in the fragments. A product then costs one pass over the
// fragments (8 bytes each) instead of one over H's non-zeros (8 bytes each, several times as
// many on dense views), and H is never built. This is Algorithm 1's sum without the clamp to 1
// of core/occlusion_matrix.h (an entry exceeds 1 only when part i has two fragments in front of
// most of part j's: the joints of its segments); occlusionMatrixReference(lists, n, false) is the
// same matrix assembled. What it cannot give cheaply is a sum of squared entries (diag(Q)): see
// OpacityEnergy's constructor for the estimate the preconditioner uses. No OpenGL.
#include <tbb/enumerable_thread_specific.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/occlusion_matrix.h"

namespace tc {

class FragmentOcclusion {
public:
    // `lists` sorted front to back (FragmentLists::sortByDepth); only lists of two or more
    // fragments are kept (a single fragment occludes nothing and is occluded by nothing).
    // `blockSlots`: the local array size a block of lists may use (see multiply()); tests pass
    // small values to get many blocks.
    // 0 (the default) chooses: kBlockSlots, grown while the blocks' gathers exceed a quarter of
    // the fragments (deep lists of many distinct parts, see formBlocks).
    FragmentOcclusion(const FragmentLists& lists, std::size_t partCount, std::size_t blockSlots = 0);

    // Parts are gathered in groups of kGroup consecutive ids (a polyline's parts are consecutive),
    // each with kGroupSlots = kGroup + 1 local slots. 16384 slots (1820 groups; the automatic
    // choice starts there): a block's two local arrays (256 KB) and its fragments stay in L2 (2 MB
    // per core here); at 128k parts 4096 slots made blocks so small that the gathers cost more
    // than they saved (docs/performance.md).
    static constexpr std::uint32_t kGroup = 8, kGroupSlots = kGroup + 1;
    static constexpr std::size_t kBlockSlots = 16384;

    std::size_t partCount() const { return m_n; }
    // Fragments kept (in lists of at least two) and the pairs Algorithm 1 would visit.
    std::size_t fragmentCount() const { return m_fragments.size(); }
    std::uint64_t pairCount() const { return m_pairs; }

    // hx = H x and htx = H^T y in one pass over the fragments (either output may be null; its
    // input is then not read). The lists are kept in Z order over the image and cut into blocks
    // that touch at most blockSlots / kGroupSlots groups of parts, with fragments holding
    // block-local slot ids: per block the inputs are gathered into a local array, the lists are
    // walked there (in cache), and the local sums are scattered back once. Parallel over runs of
    // blocks (oneTBB); the scattered sums go to per-chunk buffers that are added afterwards (no
    // atomics). Not for concurrent calls on one object (the per-chunk sums are kept across calls).
    void multiply(const Eigen::VectorXd* x, Eigen::VectorXd* hx, const Eigen::VectorXd* y, Eigen::VectorXd* htx) const;

private:
    struct Fragment {
        std::uint32_t part;  // block-local slot of floor(w); floor(w) + 1 is the next slot
        float frac;          // w - floor(w)
    };
    struct Block {
        std::size_t listBegin, listEnd;    // lists [listBegin, listEnd)
        std::size_t groupBegin, groupEnd;  // m_groups[groupBegin + k]: the group of slots [9k, 9k + 9)
    };
    std::size_t m_n = 0;
    std::vector<Fragment> m_fragments;       // lists of >= 2 fragments, front to back, Z order
    std::vector<std::uint64_t> m_listStart;  // list k = [m_listStart[k], m_listStart[k + 1])
    std::vector<Block> m_blocks;
    std::vector<std::uint32_t> m_groups;  // per block, its groups (part / kGroup) ascending
    std::size_t m_blockSlots = 0;         // the largest block's slot count
    std::vector<std::size_t> m_chunks;    // block ranges of about equal fragments
    Eigen::VectorXd m_inverseCount;       // 1 / part j's fragment count, 0 for parts never seen
    Eigen::VectorXd m_self;               // d: S's diagonal (pairs of a part with itself)
    std::uint64_t m_pairs = 0;
    // A block-local slot: both inputs and both sums of a part side by side, so that a fragment's
    // four accesses (x and y at floor(w), floor(w) + 1; the two sums) hit one or two cache lines
    // instead of up to eight in four separate arrays.
    struct Slot {
        double x, y, hx, hty;
    };
    // Each thread's block-local slots and per-list scratch, kept from product to product: with
    // large blocks (deep lists, see formBlocks) they are megabytes, and allocating and
    // zeroing them per product cost more than the walk at 128k parts with subsampled lists.
    struct LocalArrays {
        std::vector<Slot> slots;
        std::vector<double> prefix, weighted;  // per fragment of the list being walked
    };
    mutable std::vector<Eigen::VectorXd> m_outH, m_outT;  // per chunk, kept across calls
    std::size_t m_longestList = 0;
    std::unique_ptr<tbb::enumerable_thread_specific<LocalArrays>> m_locals;

    // The constructor's steps, in order. The lists of two or more fragments as (Z-order code,
    // pixel), sorted: list k of m_listStart is pixel order[k].second.
    using ListOrder = std::vector<std::pair<std::uint64_t, std::uint32_t>>;
    ListOrder orderLists(const FragmentLists& lists);
    void formBlocks(const FragmentLists& lists, const ListOrder& order, std::size_t blockSlots);
    void cutChunks(std::size_t threads);
    void sumSelfPairs(const FragmentLists& lists, const ListOrder& order);
    class BlockFormer;  // formBlocks' greedy cut of the lists into blocks (fragment_occlusion.cpp)
};

}  // namespace tc
