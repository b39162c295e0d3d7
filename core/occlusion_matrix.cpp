#include "core/occlusion_matrix.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

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

// Applies the normalisation by part j's fragment count and builds the compressed rows from
// (key, weight) records sorted by key, each key once.
SparseMatrixD buildNormalised(const std::vector<std::pair<std::uint64_t, double>>& sorted,
                              const std::vector<double>& counts, std::size_t n, bool clampToOne) {
    SparseMatrixD h{Eigen::Index(n), Eigen::Index(n)};
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(sorted.size());
    for (const auto& [key, value] : sorted) {
        const std::uint32_t i = std::uint32_t(key >> 32), j = std::uint32_t(key & 0xFFFFFFFFu);
        if (counts[j] <= 0) continue;
        triplets.emplace_back(int(i), int(j), clampToOne ? std::min(1.0, value / counts[j]) : value / counts[j]);
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

FragmentLists subsampleLists(const FragmentLists& lists, int height, double scale) {
    TC_CHECK(lists.width > 0);
    TC_CHECK(scale > 0 && scale <= 1);
    const int width = lists.width;
    TC_CHECK_OP(std::size_t(width) * std::size_t(height), ==, lists.pixelCount());
    const int w = std::max(1, int(std::floor(double(width) * scale)));
    const int h = std::max(1, int(std::floor(double(height) * scale)));
    auto source = [&](int x, int size) { return std::min(size - 1, int(std::floor((double(x) + 0.5) / scale))); };
    FragmentLists out;
    out.width = w;
    out.offsets.assign(std::size_t(w) * std::size_t(h) + 1, 0);
    std::vector<std::size_t> from(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
            from[p] = std::size_t(source(y, height)) * std::size_t(width) + std::size_t(source(x, width));
            out.offsets[p + 1] = out.offsets[p] + (lists.offsets[from[p] + 1] - lists.offsets[from[p]]);
        }
    out.fragments.resize(out.offsets.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, from.size(), 4096), [&](const auto& range) {
        for (std::size_t p = range.begin(); p != range.end(); ++p)
            std::copy(lists.fragments.begin() + std::ptrdiff_t(lists.offsets[from[p]]),
                      lists.fragments.begin() + std::ptrdiff_t(lists.offsets[from[p] + 1]),
                      out.fragments.begin() + std::ptrdiff_t(out.offsets[p]));
    });
    return out;
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

SparseMatrixD occlusionMatrixReference(const FragmentLists& lists, std::size_t partCount, bool clampToOne) {
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
    return buildNormalised(sorted, partFragmentCounts(lists, partCount), partCount, clampToOne);
}

namespace {

// One thread's share of the fast path. Pixels are walked in small tiles: neighbouring pixels see
// nearly the same parts, so a tile's sums go into a dense matrix over the tile's parts (local
// ids), which stays in cache and needs no hashing; a tile's distinct pairs are then flushed as
// records (i, j, sum). Far fewer records than per-pixel pairs leave the tile.
class TileAccumulator {
public:
    static constexpr int kMaxLocal = 512;  // 512^2 doubles = 2 MB per thread

    // Sized for `partCount` parts; kept from call to call (OcclusionAssembler), so this only
    // allocates on first use or when the part count changes. Between tiles every local id is -1
    // and every sum 0 again (flush).
    void prepare(std::size_t partCount) {
        if (m_localId.size() != partCount) m_localId.assign(partCount, -1);
        if (m_sum.empty()) m_sum.assign(std::size_t(kMaxLocal) * kMaxLocal, 0.0);
    }

    // Algorithm 1 on one sorted list. The fragments in front of B enter as distinct front parts
    // with their multiplicity (a line's adjacent segments overlap at joints, so a part often has
    // two fragments in one pixel): sum_{A in front} w(B) = sum_{distinct i} count_i w(B).
    void addPixel(const LineFragmentW* f, std::size_t count) {
        if (count < 2) return;
        // Local ids for every part this pixel touches first, so no flush happens mid-pixel.
        if (!assignLocal(f, count)) {
            flush();
            if (!assignLocal(f, count)) {
                addPixelSlow(f, count);
                return;
            }
        }
        m_fronts.clear();
        for (std::size_t b = 0; b < count; ++b) {
            const LineFragmentW& fb = f[b];
            if (b > 0) {
                const int j = local(fb.part);
                const int j1 = fb.frac > 0 ? local(fb.part + 1) : -1;
                const double w0 = 1.0 - double(fb.frac), w1 = double(fb.frac);
                for (const auto& [i, c] : m_fronts) {
                    if (i != j) add(i, j, c * w0);
                    if (j1 >= 0 && i != j1) add(i, j1, c * w1);
                }
            }
            const int i = local(frontPart(fb));
            auto it = std::find_if(m_fronts.begin(), m_fronts.end(), [&](const auto& e) { return e.first == i; });
            if (it != m_fronts.end())
                it->second += 1.0;
            else
                m_fronts.emplace_back(i, 1.0);
        }
    }

    // Moves the tile's sums into the records and forgets the tile's parts.
    void flush() {
        for (std::uint32_t slot : m_touched) {
            const std::uint32_t li = slot / kMaxLocal, lj = slot % kMaxLocal;
            records.push_back({m_parts[li], m_parts[lj], m_sum[slot]});
            m_sum[slot] = 0;
        }
        m_touched.clear();
        for (std::uint32_t part : m_parts) m_localId[part] = -1;
        m_parts.clear();
    }

    struct Record {
        std::uint32_t i, j;
        double value;
    };
    std::vector<Record> records;

private:
    int local(std::uint32_t part) {
        int& id = m_localId[part];
        if (id < 0) {
            id = int(m_parts.size());
            m_parts.push_back(part);
        }
        return id;
    }
    // Gives every part of the list a local id; false (and nothing changed) if they do not fit.
    bool assignLocal(const LineFragmentW* f, std::size_t count) {
        const std::size_t before = m_parts.size();
        for (std::size_t k = 0; k < count && m_parts.size() <= std::size_t(kMaxLocal); ++k) {
            local(frontPart(f[k]));
            local(f[k].part);
            if (f[k].frac > 0) local(f[k].part + 1);
        }
        if (m_parts.size() <= std::size_t(kMaxLocal)) return true;
        for (std::size_t k = before; k < m_parts.size(); ++k) m_localId[m_parts[k]] = -1;
        m_parts.resize(before);
        return false;
    }
    void add(int i, int j, double w) {
        const std::uint32_t slot = std::uint32_t(i) * kMaxLocal + std::uint32_t(j);
        if (m_sum[slot] == 0) m_touched.push_back(slot);  // weights are positive: 0 = untouched
        m_sum[slot] += w;
    }
    // A single list deeper than the local matrix holds: pairs go to the records directly.
    void addPixelSlow(const LineFragmentW* f, std::size_t count) {
        for (std::size_t a = 0; a + 1 < count; ++a) {
            const std::uint32_t i = frontPart(f[a]);
            for (std::size_t b = a + 1; b < count; ++b) {
                if (i != f[b].part) records.push_back({i, f[b].part, 1.0 - double(f[b].frac)});
                if (f[b].frac > 0 && i != f[b].part + 1) records.push_back({i, f[b].part + 1, double(f[b].frac)});
            }
        }
    }

    std::vector<int> m_localId;          // global part -> local id, -1 outside the tile
    std::vector<std::uint32_t> m_parts;  // local id -> global part
    std::vector<double> m_sum;           // kMaxLocal x kMaxLocal
    std::vector<std::uint32_t> m_touched;
    std::vector<std::pair<int, double>> m_fronts;  // distinct front parts so far in the pixel
};

// A sparse accumulator per thread for the per-row merge: a dense array over the columns (all
// zero between rows) and the columns touched.
struct Spa {
    std::vector<double> sum;
    std::vector<std::uint32_t> touched;
};

}  // namespace

struct OcclusionAssembler::Buffers {
    tbb::enumerable_thread_specific<TileAccumulator> accumulators;
    std::vector<std::vector<std::uint32_t>> histogram;  // per accumulator, per row
    std::vector<std::uint64_t> rowStart;
    std::vector<std::pair<std::uint32_t, double>> byRow;  // never shrinks: its pages stay mapped
    tbb::enumerable_thread_specific<Spa> spas;
    std::vector<int> rowNonZeros;
};

OcclusionAssembler::OcclusionAssembler() = default;
OcclusionAssembler::~OcclusionAssembler() = default;
OcclusionAssembler::OcclusionAssembler(OcclusionAssembler&&) noexcept = default;
OcclusionAssembler& OcclusionAssembler::operator=(OcclusionAssembler&&) noexcept = default;

void OcclusionAssembler::release() {
    m_buffers.reset();
}

void OcclusionAssembler::assemble(const FragmentLists& lists, std::size_t partCount, SparseMatrixF& h) {
    if (!m_buffers) m_buffers = std::make_unique<Buffers>();
    Buffers& buffers = *m_buffers;
    const std::size_t pixels = lists.pixelCount();
    const std::size_t width = lists.width > 0 ? std::size_t(lists.width) : std::max<std::size_t>(pixels, 1);
    const std::size_t height = (pixels + width - 1) / width;
    // 32 x 32 tiles: 7.7 M records for 22 M pairs at 8k parts (16 x 8 tiles: 10.8 M, and the
    // record sort costs more than the larger local matrix).
    constexpr std::size_t kTileW = 32, kTileH = 32;
    const std::size_t tilesX = (width + kTileW - 1) / kTileW, tilesY = (height + kTileH - 1) / kTileH;

    // 1. Tiles in parallel, each thread with its own accumulator: no shared writes. The records
    // keep their capacity from the last call.
    for (TileAccumulator& acc : buffers.accumulators) acc.records.clear();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tilesX * tilesY, 16), [&](const auto& range) {
        TileAccumulator& acc = buffers.accumulators.local();
        acc.prepare(partCount);
        for (std::size_t t = range.begin(); t != range.end(); ++t) {
            const std::size_t x0 = (t % tilesX) * kTileW, y0 = (t / tilesX) * kTileH;
            for (std::size_t y = y0; y < std::min(y0 + kTileH, height); ++y)
                for (std::size_t x = x0; x < std::min(x0 + kTileW, width); ++x) {
                    const std::size_t p = y * width + x;
                    if (p >= pixels) break;
                    const std::uint64_t begin = lists.offsets[p], end = lists.offsets[p + 1];
                    acc.addPixel(lists.fragments.data() + begin, std::size_t(end - begin));
                }
            acc.flush();
        }
    });

    // 2. Records -> compressed rows: a counting sort on i (each thread scatters its own records
    // into slots reserved per row), then per row a sparse accumulator (a dense array over the
    // columns plus the list of columns touched) sums duplicates in time linear in the records.
    std::vector<std::vector<TileAccumulator::Record>*> sources;
    for (TileAccumulator& acc : buffers.accumulators) sources.push_back(&acc.records);
    const std::size_t threads = sources.size();
    std::vector<std::vector<std::uint32_t>>& histogram = buffers.histogram;
    histogram.resize(threads);
    tbb::parallel_for(std::size_t(0), threads, [&](std::size_t t) {
        histogram[t].assign(partCount, 0);
        for (const auto& r : *sources[t]) ++histogram[t][r.i];
    });
    std::vector<std::uint64_t>& rowStart = buffers.rowStart;
    rowStart.assign(partCount + 1, 0);
    for (std::size_t i = 0; i < partCount; ++i) {
        std::uint64_t at = rowStart[i];
        for (std::size_t t = 0; t < threads; ++t) {
            const std::uint32_t count = histogram[t][i];
            histogram[t][i] = std::uint32_t(at - rowStart[i]);  // the thread's offset within the row
            at += count;
        }
        rowStart[i + 1] = at;
    }
    std::vector<std::pair<std::uint32_t, double>>& byRow = buffers.byRow;
    if (byRow.size() < rowStart[partCount]) byRow.resize(rowStart[partCount]);
    tbb::parallel_for(std::size_t(0), threads, [&](std::size_t t) {
        std::vector<std::uint32_t>& fill = histogram[t];
        for (const auto& r : *sources[t]) byRow[rowStart[r.i] + fill[r.i]++] = {r.j, r.value};
    });

    const std::vector<double> counts = partFragmentCounts(lists, partCount);
    std::vector<int>& rowNonZeros = buffers.rowNonZeros;
    rowNonZeros.assign(partCount, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, partCount, 64), [&](const auto& range) {
        Spa& spa = buffers.spas.local();
        if (spa.sum.size() != partCount) spa.sum.assign(partCount, 0.0);
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const std::uint64_t first = rowStart[i], last = rowStart[i + 1];
            for (std::uint64_t k = first; k < last; ++k) {
                const auto& [j, value] = byRow[k];
                if (spa.sum[j] == 0) spa.touched.push_back(j);  // sums are positive: 0 = untouched
                spa.sum[j] += value;
            }
            std::sort(spa.touched.begin(), spa.touched.end());
            // Normalised by part j's fragment count (columns nobody covers stay out), clamped to
            // 1; written over the row's own records (a row has at least as many records as columns).
            std::uint64_t out = first;
            for (std::uint32_t j : spa.touched) {
                if (counts[j] > 0) byRow[out++] = {j, std::min(1.0, spa.sum[j] / counts[j])};
                spa.sum[j] = 0;
            }
            spa.touched.clear();
            rowNonZeros[i] = int(out - first);
        }
    });

    // 3. The compressed rows in single precision, each value rounded once from its double sum,
    // into h's own arrays when they are large enough (resize keeps them).
    h.resize(Eigen::Index(partCount), Eigen::Index(partCount));
    std::int64_t total = 0;
    for (std::size_t i = 0; i < partCount; ++i) total += rowNonZeros[i];
    TC_CHECK_OP(total, <=, std::int64_t(std::numeric_limits<int>::max()));
    // H's non-zeros change a little from frame to frame: some headroom when the arrays must grow.
    if (h.data().allocatedSize() < total) h.data().reserve(Eigen::Index(total + total / 16));
    h.resizeNonZeros(Eigen::Index(total));
    int* outer = h.outerIndexPtr();
    int* inner = h.innerIndexPtr();
    float* values = h.valuePtr();
    outer[0] = 0;
    for (std::size_t i = 0; i < partCount; ++i) outer[i + 1] = outer[i] + rowNonZeros[i];
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, partCount, 256), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i)
            for (int k = 0; k < rowNonZeros[i]; ++k) {
                const auto& [j, value] = byRow[rowStart[i] + std::uint64_t(k)];
                inner[outer[i] + k] = int(j);
                values[outer[i] + k] = float(value);
            }
    });
}

SparseMatrixF occlusionMatrix(const FragmentLists& lists, std::size_t partCount) {
    OcclusionAssembler assembler;
    SparseMatrixF h;
    assembler.assemble(lists, partCount, h);
    return h;
}

}  // namespace tc
