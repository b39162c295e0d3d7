#include "core/fragment_occlusion.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "core/error.h"

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

FragmentOcclusion::FragmentOcclusion(const FragmentLists& lists, std::size_t partCount, std::size_t blockParts)
    : m_n(partCount) {
    TC_CHECK(blockParts >= 2 && blockParts <= 65536);
    m_blockParts = 0;
    // Part counts over all fragments (singletons included: they are part of j's pixels).
    const std::vector<double> counts = partFragmentCounts(lists, partCount);
    m_inverseCount.resize(Eigen::Index(partCount));
    for (std::size_t j = 0; j < partCount; ++j) m_inverseCount[Eigen::Index(j)] = counts[j] > 0 ? 1.0 / counts[j] : 0.0;

    // The lists that matter (two or more fragments), in Z order over the image: neighbouring
    // pixels see nearly the same parts, so a run of lists in this order touches few distinct parts.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order;
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
    }
    const std::uint64_t fragmentTotal = m_listStart.back();

    // Blocks: runs of consecutive lists whose fragments touch at most blockParts distinct parts
    // (floor(w) and floor(w) + 1 of every fragment). A product gathers a block's inputs into
    // arrays over its local part ids, walks its lists there (in L1/L2 instead of scattered over
    // n-long vectors: the cache misses that made the 128k product 8x the 32k one for 3.7x the
    // fragments), and scatters the local sums back once per block. Formed greedily in a few
    // independent ranges of lists, in parallel; local ids are 16 bits. Measured at 128k parts
    // (docs/performance.md M7 session 5): 33.5 M fragments, 1036 blocks of 4096 parts, 4.1 M
    // gathered entries per pass; 2048 parts per block gives 9.5 M, 1024 parts 29 M (a 32 x 32 px
    // region of this dense view already sees ~1000 parts), float local arrays gained nothing.
    const std::size_t threads = std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    const std::size_t ranges = fragmentTotal < 50000 ? 1 : 8 * threads;
    std::vector<std::size_t> rangeStart(1, 0);
    for (std::size_t r = 1; r < ranges; ++r) {
        const std::uint64_t target = fragmentTotal * r / ranges;
        const std::size_t list =
            std::size_t(std::lower_bound(m_listStart.begin(), m_listStart.end(), target) - m_listStart.begin());
        if (list > rangeStart.back() && list < listCount) rangeStart.push_back(list);
    }
    rangeStart.push_back(listCount);
    m_fragments.resize(fragmentTotal);
    struct RangeBlocks {
        std::vector<Block> blocks;
        std::vector<std::uint32_t> globals;
    };
    std::vector<RangeBlocks> perRange(rangeStart.size() - 1);
    struct Marks {
        std::vector<std::uint32_t> local;  // part -> local id + 1 in the current block, 0 if not in it
    };
    tbb::enumerable_thread_specific<Marks> marks([&] { return Marks{std::vector<std::uint32_t>(partCount + 1, 0)}; });
    tbb::parallel_for(std::size_t(0), perRange.size(), [&](std::size_t r) {
        std::vector<std::uint32_t>& local = marks.local().local;
        RangeBlocks& out = perRange[r];
        std::vector<std::uint32_t> globals;  // the current block's parts, by local id
        std::vector<std::uint16_t> toSorted;
        auto closeBlock = [&](std::size_t firstList, std::size_t endList) {
            // Local ids in ascending global order, so the gather and scatter walk memory forwards.
            std::vector<std::uint32_t> sorted = globals;
            std::sort(sorted.begin(), sorted.end());
            toSorted.resize(globals.size());
            for (std::size_t k = 0; k < sorted.size(); ++k) local[sorted[k]] = std::uint32_t(k) + 1;
            for (std::size_t k = 0; k < globals.size(); ++k) toSorted[k] = std::uint16_t(local[globals[k]] - 1);
            for (std::uint64_t f = m_listStart[firstList]; f < m_listStart[endList]; ++f) {
                m_fragments[f].front = toSorted[m_fragments[f].front];
                m_fragments[f].back = toSorted[m_fragments[f].back];
            }
            for (std::uint32_t g : sorted) local[g] = 0;
            out.blocks.push_back({firstList, endList, out.globals.size(), out.globals.size() + sorted.size()});
            out.globals.insert(out.globals.end(), sorted.begin(), sorted.end());
            globals.clear();
        };
        std::size_t blockFirst = rangeStart[r];
        for (std::size_t l = rangeStart[r]; l < rangeStart[r + 1]; ++l) {
            const std::size_t p = order[l].second;
            const LineFragmentW* f = lists.fragments.data() + lists.offsets[p];
            const std::size_t length = std::size_t(m_listStart[l + 1] - m_listStart[l]);
            // Distinct parts this list would add. A list that alone touches more than blockParts
            // parts (over blockParts / 2 fragments) becomes a block of its own, up to the 16-bit
            // limit of the local ids.
            std::size_t added = 0;
            for (std::size_t k = 0; k < length; ++k) {
                const std::uint32_t j = f[k].part;
                added += local[j] == 0;
                if (local[j] == 0) local[j] = ~0u;
                if (f[k].frac > 0 && local[j + 1] == 0) {
                    local[j + 1] = ~0u;
                    ++added;
                }
            }
            for (std::size_t k = 0; k < length; ++k) {  // undo the probe marks
                const std::uint32_t j = f[k].part;
                if (local[j] == ~0u) local[j] = 0;
                if (local[j + 1] == ~0u) local[j + 1] = 0;
            }
            if (globals.size() + added > blockParts && l > blockFirst) {
                closeBlock(blockFirst, l);
                blockFirst = l;
            }
            TC_CHECK_OP(added, <=, std::size_t(65536));
            Fragment* dst = m_fragments.data() + m_listStart[l];
            auto localId = [&](std::uint32_t j) {
                if (local[j] == 0) {
                    globals.push_back(j);
                    local[j] = std::uint32_t(globals.size());
                }
                return std::uint16_t(local[j] - 1);
            };
            for (std::size_t k = 0; k < length; ++k) {
                const std::uint32_t j = f[k].part;
                const std::uint16_t front = localId(j);
                // frac = 0 (a polyline's last part): no weight to j + 1, which may not exist.
                const std::uint16_t back = f[k].frac > 0 ? localId(j + 1) : front;
                dst[k] = {front, back, f[k].frac};
            }
        }
        if (rangeStart[r + 1] > blockFirst) closeBlock(blockFirst, rangeStart[r + 1]);
    });
    // Concatenate the ranges' blocks; chunks for the product are runs of blocks of about equal
    // fragments, a few per thread so one slowed thread does not hold the pass up.
    for (RangeBlocks& rb : perRange) {
        const std::size_t base = m_globals.size();
        for (Block b : rb.blocks) {
            b.globalBegin += base;
            b.globalEnd += base;
            m_blocks.push_back(b);
        }
        m_globals.insert(m_globals.end(), rb.globals.begin(), rb.globals.end());
    }
    const std::size_t chunks = fragmentTotal < 50000 ? 1 : 2 * threads;
    m_chunks.assign(1, 0);
    for (std::size_t c = 1; c < chunks; ++c) {
        const std::uint64_t target = fragmentTotal * c / chunks;
        std::size_t b = m_chunks.back();
        while (b < m_blocks.size() && m_listStart[m_blocks[b].listBegin] < target) ++b;
        if (b > m_chunks.back() && b < m_blocks.size()) m_chunks.push_back(b);
    }
    m_chunks.push_back(m_blocks.size());
    for (const Block& b : m_blocks) m_blockParts = std::max(m_blockParts, b.globalEnd - b.globalBegin);

    // d_i: for each B, the A in front of it whose front part is the part B's weight goes to.
    // A per-thread count of front parts seen in the current list (reset after each list), in the
    // blocks' local ids.
    struct Scratch {
        std::vector<std::uint32_t> seen;
        Eigen::VectorXd self;
    };
    tbb::enumerable_thread_specific<Scratch> scratch(
        [&] { return Scratch{std::vector<std::uint32_t>(m_blockParts, 0), Eigen::VectorXd::Zero(Eigen::Index(partCount))}; });
    tbb::parallel_for(std::size_t(0), m_blocks.size(), [&](std::size_t bi) {
        Scratch& s = scratch.local();
        const Block& block = m_blocks[bi];
        const std::uint32_t* global = m_globals.data() + block.globalBegin;
        for (std::size_t l = block.listBegin; l < block.listEnd; ++l) {
            const Fragment* f = m_fragments.data() + m_listStart[l];
            const std::size_t length = std::size_t(m_listStart[l + 1] - m_listStart[l]);
            for (std::size_t b = 0; b < length; ++b) {
                const std::uint16_t j0 = f[b].front, j1 = f[b].back;
                if (s.seen[j0]) s.self[global[j0]] += double(s.seen[j0]) * (1.0 - double(f[b].frac));
                if (f[b].frac > 0 && s.seen[j1]) s.self[global[j1]] += double(s.seen[j1]) * double(f[b].frac);
                ++s.seen[f[b].frac >= 0.5f ? j1 : j0];
            }
            for (std::size_t b = 0; b < length; ++b) s.seen[f[b].frac >= 0.5f ? f[b].back : f[b].front] = 0;
        }
    });
    m_self = Eigen::VectorXd::Zero(Eigen::Index(partCount));
    for (const Scratch& s : scratch) m_self += s.self;
}

// The local id of round(w), without a branch (a mispredicted branch per fragment costs more than
// the arithmetic on these short, unpredictable lists).
inline std::uint32_t FragmentOcclusion::roundId(const Fragment& f) {
    const std::uint32_t mask = 0u - std::uint32_t(f.frac >= 0.5f);
    return std::uint32_t(f.front) ^ ((std::uint32_t(f.front) ^ std::uint32_t(f.back)) & mask);
}

void FragmentOcclusion::multiply(const Eigen::VectorXd* x, Eigen::VectorXd* hx, const Eigen::VectorXd* y,
                                 Eigen::VectorXd* htx) const {
    const Eigen::Index n = Eigen::Index(m_n);
    if (hx) TC_CHECK(x && x->size() == n);
    if (htx) TC_CHECK(y && y->size() == n);
    // H x = S (N x) - d . (N x): the suffix sums see N x.
    Eigen::VectorXd xs;
    if (hx) xs = m_inverseCount.cwiseProduct(*x);
    const double* xv = hx ? xs.data() : nullptr;
    const double* yv = htx ? y->data() : nullptr;
    const std::size_t chunks = m_chunks.size() - 1;
    // Per-chunk outputs: S N x scatters into the front parts, S^T y into the parts behind.
    std::vector<Eigen::VectorXd> outH(hx ? chunks : 0), outT(htx ? chunks : 0);
    struct Local {
        std::vector<double> x, y, h, t;
    };
    tbb::enumerable_thread_specific<Local> locals([&] {
        return Local{std::vector<double>(m_blockParts), std::vector<double>(m_blockParts),
                     std::vector<double>(m_blockParts), std::vector<double>(m_blockParts)};
    });
    const auto body = [&](std::size_t c) {
        Local& local = locals.local();
        double* oh = nullptr;
        double* ot = nullptr;
        if (hx) {
            outH[c].setZero(n);
            oh = outH[c].data();
        }
        if (htx) {
            outT[c].setZero(n);
            ot = outT[c].data();
        }
        const Fragment* fragments = m_fragments.data();
        const std::uint64_t* start = m_listStart.data();
        double* lx = local.x.data();
        double* ly = local.y.data();
        double* lh = local.h.data();
        double* lt = local.t.data();
        for (std::size_t bi = m_chunks[c]; bi < m_chunks[c + 1]; ++bi) {
            const Block& block = m_blocks[bi];
            const std::uint32_t* global = m_globals.data() + block.globalBegin;
            const std::size_t parts = block.globalEnd - block.globalBegin;
            if (htx) {
                for (std::size_t k = 0; k < parts; ++k) ly[k] = yv[global[k]];
                std::fill(lt, lt + parts, 0.0);
                for (std::size_t l = block.listBegin; l < block.listEnd; ++l) {
                    // Front to back: P = sum of y over the front parts of the fragments in front.
                    double prefix = 0;
                    for (std::uint64_t b = start[l]; b < start[l + 1]; ++b) {
                        const Fragment f = fragments[b];
                        const double w1 = double(f.frac);
                        lt[f.front] += (1.0 - w1) * prefix;
                        lt[f.back] += w1 * prefix;
                        prefix += ly[roundId(f)];
                    }
                }
                for (std::size_t k = 0; k < parts; ++k) ot[global[k]] += lt[k];
            }
            if (hx) {
                for (std::size_t k = 0; k < parts; ++k) lx[k] = xv[global[k]];
                std::fill(lh, lh + parts, 0.0);
                for (std::size_t l = block.listBegin; l < block.listEnd; ++l) {
                    // Back to front: T = sum of the weighted N x over the fragments behind.
                    double suffix = 0;
                    for (std::uint64_t a = start[l + 1]; a-- > start[l];) {
                        const Fragment f = fragments[a];
                        const double w1 = double(f.frac);
                        lh[roundId(f)] += suffix;
                        suffix += (1.0 - w1) * lx[f.front] + w1 * lx[f.back];
                    }
                }
                for (std::size_t k = 0; k < parts; ++k) oh[global[k]] += lh[k];
            }
        }
    };
    if (chunks == 1)
        body(0);
    else
        tbb::parallel_for(std::size_t(0), chunks, body);
    if (hx) {
        *hx = std::move(outH[0]);
        for (std::size_t c = 1; c < chunks; ++c) *hx += outH[c];
        *hx -= m_self.cwiseProduct(xs);
    }
    if (htx) {
        *htx = std::move(outT[0]);
        for (std::size_t c = 1; c < chunks; ++c) *htx += outT[c];
        *htx = m_inverseCount.cwiseProduct(*htx - m_self.cwiseProduct(*y));
    }
}

}  // namespace tc
