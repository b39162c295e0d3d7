#include "core/occlusion_matrix.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/error.h"

namespace tc {

namespace {

std::uint64_t pairKey(std::uint32_t i, std::uint32_t j) {
    return (std::uint64_t(i) << 32) | j;
}

// The part of a fragment in front: round(w).
std::uint32_t frontPart(const LineFragmentW& f) {
    return f.frac >= 0.5f ? f.part + 1 : f.part;
}

// Open-addressing hash map from (i, j) to an accumulated weight. Hand-written because the sum
// touches every front/back pair of every pixel (millions per frame) and std::unordered_map's node
// allocations dominate such a loop; linear probing on a flat power-of-two table does not allocate.
class PairAccumulator {
public:
    PairAccumulator() : m_keys(1u << 12, kEmpty), m_values(1u << 12, 0.0) {}

    void add(std::uint64_t key, double value) {
        if (2 * (m_size + 1) > m_keys.size()) grow();
        std::size_t mask = m_keys.size() - 1, slot = hash(key) & mask;
        while (m_keys[slot] != kEmpty && m_keys[slot] != key) slot = (slot + 1) & mask;
        if (m_keys[slot] == kEmpty) {
            m_keys[slot] = key;
            ++m_size;
        }
        m_values[slot] += value;
    }

    template <class F>
    void forEach(F&& f) const {
        for (std::size_t s = 0; s < m_keys.size(); ++s)
            if (m_keys[s] != kEmpty) f(m_keys[s], m_values[s]);
    }
    std::size_t size() const { return m_size; }

private:
    static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
    static std::size_t hash(std::uint64_t k) { return std::size_t((k * 0x9E3779B97F4A7C15ull) >> 17); }
    void grow() {
        std::vector<std::uint64_t> keys(m_keys.size() * 2, kEmpty);
        std::vector<double> values(m_keys.size() * 2, 0.0);
        std::swap(keys, m_keys);
        std::swap(values, m_values);
        m_size = 0;
        for (std::size_t s = 0; s < keys.size(); ++s)
            if (keys[s] != kEmpty) add(keys[s], values[s]);
    }

    std::vector<std::uint64_t> m_keys;
    std::vector<double> m_values;
    std::size_t m_size = 0;
};

// Applies the normalisation by part j's fragment count and builds the compressed rows from
// (key, weight) records sorted by key, each key once.
SparseMatrixD buildNormalised(const std::vector<std::pair<std::uint64_t, double>>& sorted,
                              const std::vector<double>& counts, std::size_t n) {
    SparseMatrixD h{Eigen::Index(n), Eigen::Index(n)};
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(sorted.size());
    for (const auto& [key, value] : sorted) {
        const std::uint32_t i = std::uint32_t(key >> 32), j = std::uint32_t(key & 0xFFFFFFFFu);
        if (counts[j] <= 0) continue;
        triplets.emplace_back(int(i), int(j), std::min(1.0, value / counts[j]));
    }
    h.setFromTriplets(triplets.begin(), triplets.end());
    return h;
}

}  // namespace

void FragmentLists::sortByDepth() {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixelCount(), 1024), [&](const auto& range) {
        for (std::size_t p = range.begin(); p != range.end(); ++p)
            std::sort(fragments.begin() + std::ptrdiff_t(offsets[p]),
                      fragments.begin() + std::ptrdiff_t(offsets[p + 1]),
                      [](const LineFragmentW& a, const LineFragmentW& b) {
                          return a.depth != b.depth ? a.depth < b.depth : a.part < b.part;
                      });
    });
}

std::vector<double> partFragmentCounts(const FragmentLists& lists, std::size_t partCount) {
    std::vector<double> counts(partCount, 0.0);
    for (const LineFragmentW& f : lists.fragments) {
        TC_CHECK_OP(std::size_t(f.part), <, partCount);
        counts[f.part] += 1.0 - f.frac;
        if (f.frac > 0) {
            TC_CHECK_OP(std::size_t(f.part) + 1, <, partCount);
            counts[f.part + 1] += f.frac;
        }
    }
    return counts;
}

SparseMatrixD occlusionMatrixReference(const FragmentLists& lists, std::size_t partCount) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, double> sum;
    for (std::size_t p = 0; p < lists.pixelCount(); ++p) {
        for (std::uint64_t a = lists.offsets[p]; a < lists.offsets[p + 1]; ++a) {
            const LineFragmentW& fa = lists.fragments[a];
            const std::uint32_t i = frontPart(fa);
            for (std::uint64_t b = a + 1; b < lists.offsets[p + 1]; ++b) {
                const LineFragmentW& fb = lists.fragments[b];
                const std::uint32_t j = fb.part;
                if (i != j) sum[{i, j}] += 1.0 - fb.frac;
                if (fb.frac > 0 && i != j + 1) sum[{i, j + 1}] += fb.frac;
            }
        }
    }
    std::vector<std::pair<std::uint64_t, double>> sorted;
    for (const auto& [ij, value] : sum) sorted.emplace_back(pairKey(ij.first, ij.second), value);
    return buildNormalised(sorted, partFragmentCounts(lists, partCount), partCount);
}

SparseMatrixD occlusionMatrix(const FragmentLists& lists, std::size_t partCount) {
    tbb::enumerable_thread_specific<PairAccumulator> accumulators;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists.pixelCount(), 256), [&](const auto& range) {
        PairAccumulator& acc = accumulators.local();
        for (std::size_t p = range.begin(); p != range.end(); ++p) {
            const std::uint64_t end = lists.offsets[p + 1];
            for (std::uint64_t a = lists.offsets[p]; a + 1 < end; ++a) {
                const std::uint32_t i = frontPart(lists.fragments[a]);
                for (std::uint64_t b = a + 1; b < end; ++b) {
                    const LineFragmentW& fb = lists.fragments[b];
                    if (i != fb.part) acc.add(pairKey(i, fb.part), 1.0 - fb.frac);
                    if (fb.frac > 0 && i != fb.part + 1) acc.add(pairKey(i, fb.part + 1), fb.frac);
                }
            }
        }
    });
    std::size_t total = 0;
    for (const PairAccumulator& acc : accumulators) total += acc.size();
    std::vector<std::pair<std::uint64_t, double>> records;
    records.reserve(total);
    for (const PairAccumulator& acc : accumulators)
        acc.forEach([&](std::uint64_t key, double value) { records.emplace_back(key, value); });
    tbb::parallel_sort(records.begin(), records.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    // Merge the threads' partial sums of equal keys.
    std::size_t out = 0;
    for (std::size_t k = 0; k < records.size(); ++k) {
        if (out > 0 && records[out - 1].first == records[k].first)
            records[out - 1].second += records[k].second;
        else
            records[out++] = records[k];
    }
    records.resize(out);
    return buildNormalised(records, partFragmentCounts(lists, partCount), partCount);
}

}  // namespace tc
