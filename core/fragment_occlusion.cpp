#include "core/fragment_occlusion.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "core/error.h"

namespace tc {

FragmentOcclusion::FragmentOcclusion(const FragmentLists& lists, std::size_t partCount) : m_n(partCount) {
    // Part counts over all fragments (singletons included: they are part of j's pixels).
    const std::vector<double> counts = partFragmentCounts(lists, partCount);
    m_inverseCount.resize(Eigen::Index(partCount));
    for (std::size_t j = 0; j < partCount; ++j) m_inverseCount[Eigen::Index(j)] = counts[j] > 0 ? 1.0 / counts[j] : 0.0;

    // The lists that matter, compacted (starts serially, copies in parallel).
    std::vector<std::size_t> pixelOf;
    m_listStart.assign(1, 0);
    for (std::size_t p = 0; p < lists.pixelCount(); ++p) {
        const std::uint64_t length = lists.offsets[p + 1] - lists.offsets[p];
        if (length < 2) continue;
        pixelOf.push_back(p);
        m_listStart.push_back(m_listStart.back() + length);
        m_pairs += length * (length - 1) / 2;
    }
    const std::size_t listCount = pixelOf.size();
    m_fragments.resize(m_listStart.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, listCount, 4096), [&](const auto& range) {
        for (std::size_t l = range.begin(); l != range.end(); ++l) {
            const LineFragmentW* f = lists.fragments.data() + lists.offsets[pixelOf[l]];
            Fragment* out = m_fragments.data() + m_listStart[l];
            for (std::uint64_t k = 0; k < m_listStart[l + 1] - m_listStart[l]; ++k) out[k] = {f[k].part, f[k].frac};
        }
    });

    // List ranges of about equal fragments; a few per thread so one slowed thread does not hold
    // the pass up.
    const std::size_t threads = std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    const std::size_t chunks = m_fragments.size() < 50000 ? 1 : 2 * threads;
    m_chunks.assign(1, 0);
    for (std::size_t c = 1; c < chunks; ++c) {
        const std::uint64_t target = std::uint64_t(m_fragments.size()) * c / chunks;
        const std::size_t list = std::size_t(std::lower_bound(m_listStart.begin(), m_listStart.end(), target) -
                                             m_listStart.begin());
        if (list > m_chunks.back() && list < listCount) m_chunks.push_back(list);
    }
    m_chunks.push_back(listCount);

    // d_i: for each B, the A in front of it whose front part is the part B's weight goes to.
    // A per-thread count of front parts seen in the current list (reset after each list).
    struct Scratch {
        std::vector<std::uint32_t> seen;
        Eigen::VectorXd self;
    };
    tbb::enumerable_thread_specific<Scratch> scratch(
        [&] { return Scratch{std::vector<std::uint32_t>(partCount, 0), Eigen::VectorXd::Zero(Eigen::Index(partCount))}; });
    tbb::parallel_for(std::size_t(0), m_chunks.size() - 1, [&](std::size_t c) {
        Scratch& s = scratch.local();
        for (std::size_t l = m_chunks[c]; l < m_chunks[c + 1]; ++l) {
            const Fragment* f = m_fragments.data() + m_listStart[l];
            const std::size_t length = std::size_t(m_listStart[l + 1] - m_listStart[l]);
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
    for (const Scratch& s : scratch) m_self += s.self;
}

void FragmentOcclusion::multiply(const Eigen::VectorXd* x, Eigen::VectorXd* hx, const Eigen::VectorXd* y,
                                 Eigen::VectorXd* htx) const {
    const Eigen::Index n = Eigen::Index(m_n);
    if (hx) TC_CHECK(x && x->size() == n);
    if (htx) TC_CHECK(y && y->size() == n);
    // H x = S (N x) - d . (N x): the suffix sums see N x. The inputs and the per-chunk outputs get
    // one padding entry at n, so the weight frac(w) to part floor(w) + 1 is added without a branch
    // (frac = 0 at a polyline's last part, where floor(w) + 1 may be n): the branches cost more
    // than the arithmetic on these short, unpredictable lists.
    Eigen::VectorXd xs, ys;
    if (hx) {
        xs.resize(n + 1);
        xs.head(n) = m_inverseCount.cwiseProduct(*x);
        xs[n] = 0;
    }
    if (htx) {
        ys.resize(n + 1);
        ys.head(n) = *y;
        ys[n] = 0;
    }
    const std::size_t chunks = m_chunks.size() - 1;
    // Per-chunk outputs: S N x scatters into the front parts, S^T y into the parts behind.
    std::vector<Eigen::VectorXd> outH(hx ? chunks : 0), outT(htx ? chunks : 0);
    const auto body = [&](std::size_t c) {
        const Fragment* fragments = m_fragments.data();
        const std::uint64_t* start = m_listStart.data();
        if (htx) {
            outT[c].setZero(n + 1);
            double* ot = outT[c].data();
            const double* yv = ys.data();
            for (std::size_t l = m_chunks[c]; l < m_chunks[c + 1]; ++l) {
                // Front to back: P = sum of y over the front parts of the fragments in front.
                double prefix = 0;
                for (std::uint64_t b = start[l]; b < start[l + 1]; ++b) {
                    const std::uint32_t j = fragments[b].part;
                    const double w1 = double(fragments[b].frac);
                    ot[j] += (1.0 - w1) * prefix;
                    ot[j + 1] += w1 * prefix;
                    prefix += yv[j + (w1 >= 0.5)];
                }
            }
        }
        if (hx) {
            outH[c].setZero(n + 1);
            double* oh = outH[c].data();
            const double* xv = xs.data();
            for (std::size_t l = m_chunks[c]; l < m_chunks[c + 1]; ++l) {
                // Back to front: T = sum of the weighted N x over the fragments behind.
                double suffix = 0;
                for (std::uint64_t a = start[l + 1]; a-- > start[l];) {
                    const std::uint32_t j = fragments[a].part;
                    const double w1 = double(fragments[a].frac);
                    oh[j + (w1 >= 0.5)] += suffix;
                    suffix += (1.0 - w1) * xv[j] + w1 * xv[j + 1];
                }
            }
        }
    };
    if (chunks == 1)
        body(0);
    else
        tbb::parallel_for(std::size_t(0), chunks, body);
    if (hx) {
        *hx = outH[0].head(n);
        for (std::size_t c = 1; c < chunks; ++c) *hx += outH[c].head(n);
        *hx -= m_self.cwiseProduct(xs.head(n));
    }
    if (htx) {
        *htx = outT[0].head(n);
        for (std::size_t c = 1; c < chunks; ++c) *htx += outT[c].head(n);
        *htx = m_inverseCount.cwiseProduct(*htx - m_self.cwiseProduct(ys.head(n)));
    }
}

}  // namespace tc
