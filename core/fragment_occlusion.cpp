#include "core/fragment_occlusion.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "core/error.h"
#include "core/parallel_chunks.h"

namespace tc {

namespace {

// Interleaves the bits of x and y (Morton / Z order): consecutive codes stay in compact squares.
std::uint64_t mortonCode(std::uint32_t x, std::uint32_t y) {
    auto spread = [](std::uint64_t v) {
        v &= 0xFFFFFFFFu;
        v = (v | (v << 16)) & 0x0000FFFF0000FFFFull;
        v = (v | (v << 8)) & 0x00FF00FF00FF00FFull;
        v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0Full;
        v = (v | (v << 2)) & 0x3333333333333333ull;
        v = (v | (v << 1)) & 0x5555555555555555ull;
        return v;
    };
    return spread(x) | (spread(y) << 1);
}

}  // namespace

FragmentOcclusion::FragmentOcclusion(const FragmentLists& lists, std::size_t partCount, std::size_t blockSlots)
    : m_n(partCount), m_locals(std::make_unique<tbb::enumerable_thread_specific<LocalArrays>>()) {
    // Part counts over all fragments (singletons included: they are part of j's pixels).
    const std::vector<double> counts = partFragmentCounts(lists, partCount);
    m_inverseCount.resize(Eigen::Index(partCount));
    for (std::size_t j = 0; j < partCount; ++j) m_inverseCount[Eigen::Index(j)] = counts[j] > 0 ? 1.0 / counts[j] : 0.0;
    const ListOrder order = orderLists(lists);
    formBlocks(lists, order, blockSlots);
    sumSelfPairs(lists, order);
}

// The lists that matter (two or more fragments), in Z order over the image: neighbouring pixels
// see nearly the same parts, so a run of lists in this order touches few distinct parts. Sets
// m_pairs, m_listStart and m_longestList.
FragmentOcclusion::ListOrder FragmentOcclusion::orderLists(const FragmentLists& lists) {
    ListOrder order;
    const std::size_t width = lists.width > 0 ? std::size_t(lists.width) : lists.pixelCount();
    for (std::size_t p = 0; p < lists.pixelCount(); ++p) {
        const std::uint64_t length = lists.offsets[p + 1] - lists.offsets[p];
        if (length < 2) continue;
        m_pairs += length * (length - 1) / 2;
        order.emplace_back(mortonCode(std::uint32_t(p % width), std::uint32_t(p / width)), std::uint32_t(p));
    }
    tbb::parallel_sort(order.begin(), order.end());
    const std::size_t listCount = order.size();
    m_listStart.resize(listCount + 1);
    m_listStart[0] = 0;
    for (std::size_t l = 0; l < listCount; ++l) {
        const std::size_t p = order[l].second;
        m_listStart[l + 1] = m_listStart[l] + (lists.offsets[p + 1] - lists.offsets[p]);
        m_longestList = std::max<std::size_t>(m_longestList, std::size_t(m_listStart[l + 1] - m_listStart[l]));
    }
    return order;
}

// The greedy cut of formBlocks: the lists in ranges (one per thread), each range cut in parallel
// into blocks that gather at most `groupCap` groups. Keeps the per-range results, so that a cut
// can be tried (only counting what the blocks would gather) before the one that is kept.
class FragmentOcclusion::BlockFormer {
public:
    BlockFormer(FragmentOcclusion& owner, const FragmentLists& lists, const ListOrder& order,
                std::vector<std::size_t> rangeStart, std::size_t groupCount)
        : m_owner(owner),
          m_lists(lists),
          m_order(order),
          m_rangeStart(std::move(rangeStart)),
          m_perRange(m_rangeStart.size() - 1),
          m_marks([groupCount] { return std::vector<std::uint32_t>(groupCount, 0); }) {}

    // Forms the blocks of at most groupCap groups; with write == false only counts the groups the
    // blocks would gather (the same greedy cut, no fragment written). Returns that count.
    std::size_t form(std::size_t groupCap, bool write) {
        tbb::parallel_for(std::size_t(0), m_perRange.size(), [&](std::size_t r) { formRange(r, groupCap, write); });
        std::size_t gathered = 0;
        for (const RangeBlocks& rb : m_perRange) gathered += rb.groupCount;
        return gathered;
    }

    // Concatenates the ranges' blocks (of the last form(..., true)) into the owner's.
    void appendBlocks() {
        for (RangeBlocks& rb : m_perRange) {
            const std::size_t base = m_owner.m_groups.size();
            for (Block b : rb.blocks) {
                b.groupBegin += base;
                b.groupEnd += base;
                m_owner.m_blocks.push_back(b);
            }
            m_owner.m_groups.insert(m_owner.m_groups.end(), rb.groups.begin(), rb.groups.end());
        }
    }

private:
    struct RangeBlocks {
        std::vector<Block> blocks;
        std::vector<std::uint32_t> groups;
        std::size_t groupCount = 0;  // gathered groups (also when the blocks are only counted)
    };

    void formRange(std::size_t r, std::size_t groupCap, bool write);

    FragmentOcclusion& m_owner;
    const FragmentLists& m_lists;
    const ListOrder& m_order;
    const std::vector<std::size_t> m_rangeStart;
    std::vector<RangeBlocks> m_perRange;
    // Per thread: group -> local index + 1 in the open block, 0: not in it.
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> m_marks;
};

void FragmentOcclusion::BlockFormer::formRange(std::size_t r, std::size_t groupCap, bool write) {
    const std::vector<std::uint64_t>& listStart = m_owner.m_listStart;
    std::vector<Fragment>& fragments = m_owner.m_fragments;
    std::vector<std::uint32_t>& local = m_marks.local();
    RangeBlocks& out = m_perRange[r];
    out = {};
    std::vector<std::uint32_t> groups;  // the open block's groups, by local index
    std::vector<std::uint32_t> toSorted;
    auto closeBlock = [&](std::size_t firstList, std::size_t endList) {
        out.groupCount += groups.size();
        if (!write) {
            for (std::uint32_t g : groups) local[g] = 0;
            groups.clear();
            return;
        }
        // Groups in ascending order, so the gather and scatter walk memory forwards.
        std::vector<std::uint32_t> sorted = groups;
        std::sort(sorted.begin(), sorted.end());
        toSorted.resize(groups.size());
        for (std::size_t k = 0; k < sorted.size(); ++k) local[sorted[k]] = std::uint32_t(k) + 1;
        for (std::size_t k = 0; k < groups.size(); ++k) toSorted[k] = local[groups[k]] - 1;
        for (std::uint64_t f = listStart[firstList]; f < listStart[endList]; ++f) {
            const std::uint32_t slot = fragments[f].part;
            fragments[f].part = toSorted[slot / kGroupSlots] * kGroupSlots + slot % kGroupSlots;
        }
        for (std::uint32_t g : sorted) local[g] = 0;
        out.blocks.push_back({firstList, endList, out.groups.size(), out.groups.size() + sorted.size()});
        out.groups.insert(out.groups.end(), sorted.begin(), sorted.end());
        groups.clear();
    };
    std::size_t blockFirst = m_rangeStart[r];
    for (std::size_t l = m_rangeStart[r]; l < m_rangeStart[r + 1]; ++l) {
        const std::size_t p = m_order[l].second;
        const LineFragmentW* f = m_lists.fragments.data() + m_lists.offsets[p];
        const std::size_t length = std::size_t(listStart[l + 1] - listStart[l]);
        // Groups this list would add (a list touching more than groupCap groups becomes a block
        // of its own).
        std::size_t added = 0;
        for (std::size_t k = 0; k < length; ++k) {
            std::uint32_t& mark = local[f[k].part / kGroup];
            if (mark == 0) {
                mark = ~0u;
                ++added;
            }
        }
        for (std::size_t k = 0; k < length; ++k)
            if (local[f[k].part / kGroup] == ~0u) local[f[k].part / kGroup] = 0;
        if (groups.size() + added > groupCap && l > blockFirst) {
            closeBlock(blockFirst, l);
            blockFirst = l;
        }
        Fragment* dst = fragments.data() + listStart[l];
        for (std::size_t k = 0; k < length; ++k) {
            const std::uint32_t j = f[k].part, g = j / kGroup;
            if (local[g] == 0) {
                groups.push_back(g);
                local[g] = std::uint32_t(groups.size());
            }
            // The slot in insertion order; closeBlock renumbers it to the sorted order.
            if (write) dst[k] = {(local[g] - 1) * kGroupSlots + j % kGroup, f[k].frac};
        }
    }
    if (m_rangeStart[r + 1] > blockFirst) closeBlock(blockFirst, m_rangeStart[r + 1]);
}

// Blocks: runs of consecutive lists whose fragments touch at most blockSlots / kGroupSlots groups
// of kGroup consecutive parts. A product gathers a block's inputs into a local array (kGroupSlots
// = kGroup + 1 slots per group: its parts and the next group's first, so that floor(w) + 1 of any
// fragment is the slot after floor(w)), walks its lists there (in L2 instead of scattered over
// n-long vectors, 1 MB each at 128k parts, where a product cost 8x the 32k one for 3.7x the
// fragments), and scatters the local sums back once per block (a part in two groups' slots gets
// both sums). The inner loops are the ones over global ids (one 32-bit id and the fraction per
// fragment, no branches). Formed greedily in one range of lists per thread, in parallel. At 128k
// parts the H product got ~1.5x cheaper, at 8k and 32k no measurable change (docs/performance.md,
// opacity optimization). One range per thread, not more: with deep lists the blocks grow to whole
// ranges (below), and every range gathers and scatters nearly all parts once per pass. Fills
// m_fragments (block-local slots), m_blocks, m_groups, m_chunks and m_blockSlots.
void FragmentOcclusion::formBlocks(const FragmentLists& lists, const ListOrder& order, std::size_t blockSlots) {
    const std::size_t listCount = order.size();
    const std::uint64_t fragmentTotal = m_listStart.back();
    const std::size_t threads = std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    const std::size_t ranges = fragmentTotal < 50000 ? 1 : threads;
    std::vector<std::size_t> rangeStart(1, 0);
    for (std::size_t r = 1; r < ranges; ++r) {
        const std::uint64_t target = fragmentTotal * r / ranges;
        const std::size_t list =
            std::size_t(std::lower_bound(m_listStart.begin(), m_listStart.end(), target) - m_listStart.begin());
        if (list > rangeStart.back() && list < listCount) rangeStart.push_back(list);
    }
    rangeStart.push_back(listCount);
    m_fragments.resize(fragmentTotal);
    const std::size_t groupCount = m_n / kGroup + 1;
    BlockFormer former(*this, lists, order, std::move(rangeStart), groupCount);
    // blockSlots 0 (the default): start at kBlockSlots and grow the blocks 4x while their gathers
    // and scatters (kGroupSlots per gathered group) exceed a quarter of the fragments walked. Deep
    // lists of many distinct parts fill a block after a few lists: at 128k parts with the lists
    // subsampled to a quarter of the width and height (render.opacity.occlusion_scale 0.25),
    // 16384-slot blocks gathered 8.9 M slots for 2.1 M fragments and a product cost 3.5x that of
    // whole-range blocks (docs/performance.md, opacity optimization). At 8k parts nothing changes
    // (0.1 M slots for 2.2 M fragments).
    std::size_t slots = blockSlots ? blockSlots : kBlockSlots;
    if (!blockSlots)
        while (slots / kGroupSlots < groupCount &&
               4 * former.form(std::max<std::size_t>(1, slots / kGroupSlots), false) * kGroupSlots > fragmentTotal)
            slots *= 4;
    former.form(std::max<std::size_t>(1, slots / kGroupSlots), true);
    former.appendBlocks();
    cutChunks(threads);
    m_blockSlots = 0;
    for (const Block& b : m_blocks) m_blockSlots = std::max(m_blockSlots, (b.groupEnd - b.groupBegin) * kGroupSlots);
}

// Chunks for the product: runs of blocks of about equal fragments, a few per thread so one slowed
// thread does not hold the pass up.
void FragmentOcclusion::cutChunks(std::size_t threads) {
    const std::uint64_t fragmentTotal = m_listStart.back();
    const std::size_t chunks = fragmentTotal < 50000 ? 1 : 2 * threads;
    m_chunks.assign(1, 0);
    for (std::size_t c = 1; c < chunks; ++c) {
        const std::uint64_t target = fragmentTotal * c / chunks;
        std::size_t b = m_chunks.back();
        while (b < m_blocks.size() && m_listStart[m_blocks[b].listBegin] < target) ++b;
        if (b > m_chunks.back() && b < m_blocks.size()) m_chunks.push_back(b);
    }
    m_chunks.push_back(m_blocks.size());
}

// d_i: for each B, the A in front of it whose front part is the part B's weight goes to. A
// per-thread count of front parts seen in the current list (reset after each list), over global
// ids (a part can have two slots in a block).
void FragmentOcclusion::sumSelfPairs(const FragmentLists& lists, const ListOrder& order) {
    struct Scratch {
        std::vector<std::uint32_t> seen;
        Eigen::VectorXd self;
    };
    const std::size_t partCount = m_n;
    tbb::enumerable_thread_specific<Scratch> scratch([&] {
        return Scratch{std::vector<std::uint32_t>(partCount + 1, 0),
                       Eigen::VectorXd::Zero(Eigen::Index(partCount + 1))};
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 1024), [&](const auto& range) {
        Scratch& s = scratch.local();
        for (std::size_t l = range.begin(); l != range.end(); ++l) {
            const std::size_t p = order[l].second;
            const LineFragmentW* f = lists.fragments.data() + lists.offsets[p];
            const std::size_t length = std::size_t(lists.offsets[p + 1] - lists.offsets[p]);
            for (std::size_t b = 0; b < length; ++b) {
                const std::uint32_t j = f[b].part;
                if (s.seen[j]) s.self[j] += double(s.seen[j]) * (1.0 - double(f[b].frac));
                if (f[b].frac > 0 && s.seen[j + 1]) s.self[j + 1] += double(s.seen[j + 1]) * double(f[b].frac);
                ++s.seen[f[b].frac >= 0.5f ? j + 1 : j];
            }
            for (std::size_t b = 0; b < length; ++b) s.seen[f[b].frac >= 0.5f ? f[b].part + 1 : f[b].part] = 0;
        }
    });
    m_self = Eigen::VectorXd::Zero(Eigen::Index(partCount));
    for (const Scratch& s : scratch) m_self += s.self.head(Eigen::Index(partCount));
}

void FragmentOcclusion::multiply(const Eigen::VectorXd* x, Eigen::VectorXd* hx, const Eigen::VectorXd* y,
                                 Eigen::VectorXd* htx) const {
    const Eigen::Index n = Eigen::Index(m_n);
    if (hx) TC_CHECK(x && x->size() == n);
    if (htx) TC_CHECK(y && y->size() == n);
    // H x = S (N x) - d . (N x): the suffix sums see N x. Inputs and outputs are padded with
    // zeros to whole groups plus the next group's first part (the last group's extra slot).
    const Eigen::Index padded = Eigen::Index((m_n / kGroup + 1) * kGroup + 1);
    Eigen::VectorXd xs, ys;
    if (hx) xs.resize(padded);
    if (htx) ys.resize(padded);
    forChunks(padded, [&](std::int64_t i0, std::int64_t i1) {
        for (std::int64_t i = i0; i < i1; ++i) {
            if (hx) xs[i] = i < n ? m_inverseCount[i] * (*x)[i] : 0.0;
            if (htx) ys[i] = i < n ? (*y)[i] : 0.0;
        }
    });
    const std::size_t chunks = m_chunks.size() - 1;
    // Per-chunk outputs (added in chunk order afterwards, so the result does not depend on which
    // thread ran which chunk), kept across calls: S N x scatters into the front parts, S^T y into
    // the parts behind.
    m_outH.resize(hx ? chunks : 0);
    m_outT.resize(htx ? chunks : 0);
    const auto body = [&](std::size_t c) {
        LocalArrays& local = m_locals->local();
        if (hx) m_outH[c].setZero(padded);
        if (htx) m_outT[c].setZero(padded);
        if (local.slots.size() < m_blockSlots) local.slots.resize(m_blockSlots);
        if (local.prefix.size() < m_longestList) {
            local.prefix.resize(m_longestList);
            local.weighted.resize(m_longestList);
        }
        const Fragment* fragments = m_fragments.data();
        const std::uint64_t* start = m_listStart.data();
        Slot* slot = local.slots.data();
        double* prefixOf = local.prefix.data();
        double* weightedOf = local.weighted.data();
        const double* xv = hx ? xs.data() : nullptr;
        const double* yv = htx ? ys.data() : nullptr;
        double* oh = hx ? m_outH[c].data() : nullptr;
        double* ot = htx ? m_outT[c].data() : nullptr;
        for (std::size_t bi = m_chunks[c]; bi < m_chunks[c + 1]; ++bi) {
            const Block& block = m_blocks[bi];
            // Gather both inputs (a missing one as zeros), zero both sums.
            for (std::size_t g = block.groupBegin; g < block.groupEnd; ++g) {
                const std::size_t src = std::size_t(m_groups[g]) * kGroup;
                Slot* dst = slot + (g - block.groupBegin) * kGroupSlots;
                for (std::uint32_t s = 0; s < kGroupSlots; ++s)
                    dst[s] = {xv ? xv[src + s] : 0.0, yv ? yv[src + s] : 0.0, 0.0, 0.0};
            }
            // Both products in two walks of each list, the second from L1: forward, the prefix of
            // y over the front parts of the fragments in front (S^T y) and each fragment's
            // weighted N x; backward, the suffix of those (S N x) and both scatters.
            for (std::size_t l = block.listBegin; l < block.listEnd; ++l) {
                const Fragment* f = fragments + start[l];
                const std::size_t length = std::size_t(start[l + 1] - start[l]);
                double prefix = 0;
                for (std::size_t k = 0; k < length; ++k) {
                    const std::uint32_t j = f[k].part;
                    const double w1 = double(f[k].frac);
                    prefixOf[k] = prefix;
                    weightedOf[k] = (1.0 - w1) * slot[j].x + w1 * slot[j + 1].x;
                    prefix += slot[j + (w1 >= 0.5)].y;
                }
                double suffix = 0;
                for (std::size_t k = length; k-- > 0;) {
                    const std::uint32_t j = f[k].part;
                    const double w1 = double(f[k].frac);
                    slot[j + (w1 >= 0.5)].hx += suffix;
                    suffix += weightedOf[k];
                    slot[j].hty += (1.0 - w1) * prefixOf[k];
                    slot[j + 1].hty += w1 * prefixOf[k];
                }
            }
            for (std::size_t g = block.groupBegin; g < block.groupEnd; ++g) {
                const std::size_t dst = std::size_t(m_groups[g]) * kGroup;
                const Slot* src = slot + (g - block.groupBegin) * kGroupSlots;
                if (oh)
                    for (std::uint32_t s = 0; s < kGroupSlots; ++s) oh[dst + s] += src[s].hx;
                if (ot)
                    for (std::uint32_t s = 0; s < kGroupSlots; ++s) ot[dst + s] += src[s].hty;
            }
        }
    };
    if (chunks == 1)
        body(0);
    else
        tbb::parallel_for(std::size_t(0), chunks, body);
    // The chunks' sums added and finished in parallel over index ranges.
    if (hx) hx->resize(n);
    if (htx) htx->resize(n);
    forChunks(n, [&](std::int64_t i0, std::int64_t i1) {
        for (std::int64_t i = i0; i < i1; ++i) {
            if (hx) {
                double sum = 0;
                for (const Eigen::VectorXd& out : m_outH) sum += out[i];
                (*hx)[i] = sum - m_self[i] * xs[i];
            }
            if (htx) {
                double sum = 0;
                for (const Eigen::VectorXd& out : m_outT) sum += out[i];
                (*htx)[i] = m_inverseCount[i] * (sum - m_self[i] * (*y)[i]);
            }
        }
    });
}

}  // namespace tc
