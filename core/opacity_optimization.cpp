#include "core/opacity_optimization.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/fragment_occlusion.h"
#include "core/parallel_chunks.h"

namespace tc {

namespace {

// y = A x over rows in parallel. Eigen parallelises sparse products only with OpenMP; the rest of
// tubecast uses oneTBB, so the row loop is spelled out here.
void multiplyRows(const SparseMatrixD& a, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
    y.resize(a.rows());
    const auto body = [&](const tbb::blocked_range<Eigen::Index>& range) {
        for (Eigen::Index row = range.begin(); row != range.end(); ++row) {
            double sum = 0;
            for (SparseMatrixD::InnerIterator it(a, row); it; ++it) sum += it.value() * x[it.index()];
            y[row] = sum;
        }
    };
    if (a.nonZeros() < 20000)
        body(tbb::blocked_range<Eigen::Index>(0, a.rows()));
    else
        tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, a.rows(), 2048), body);
}

Eigen::VectorXd clampBox(const Eigen::VectorXd& x, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
    return x.cwiseMax(lo).cwiseMin(hi);
}

// The projected gradient: the gradient with the components removed that point out of the box at
// an active bound (its negation is the steepest feasible descent direction).
double projectedComponent(double g, double x, double lo, double hi) {
    return x <= lo ? std::min(g, 0.0) : x >= hi ? std::max(g, 0.0) : g;
}

Eigen::VectorXd projectedGradient(const Eigen::VectorXd& g, const Eigen::VectorXd& x, const Eigen::VectorXd& lo,
                                  const Eigen::VectorXd& hi) {
    Eigen::VectorXd pg(g.size());
    for (Eigen::Index i = 0; i < g.size(); ++i) pg[i] = projectedComponent(g[i], x[i], lo[i], hi[i]);
    return pg;
}

}  // namespace

OpacityParts partitionLines(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& offsets,
                            int partsPerLine) {
    TC_CHECK(partsPerLine >= 1);
    TC_CHECK(!offsets.empty() && offsets.back() == positions.size());
    OpacityParts parts;
    parts.partsPerLine = partsPerLine;
    const std::size_t lines = offsets.size() - 1;
    parts.firstPart.resize(lines + 1);
    parts.vertexLocalW.resize(positions.size());
    parts.vertexFirstPart.resize(positions.size());
    const float span = float(partsPerLine - 1);
    std::vector<double> arc;
    for (std::size_t l = 0; l < lines; ++l) {
        const std::uint32_t first = std::uint32_t(l * std::size_t(partsPerLine));
        parts.firstPart[l] = first;
        const std::uint32_t v0 = offsets[l], v1 = offsets[l + 1];
        arc.assign(v1 - v0, 0.0);
        for (std::uint32_t v = v0 + 1; v < v1; ++v)
            arc[v - v0] = arc[v - v0 - 1] + double(glm::distance(positions[v - 1], positions[v]));
        const double length = arc.empty() ? 0.0 : arc.back();
        for (std::uint32_t v = v0; v < v1; ++v) {
            double t = length > 0 ? arc[v - v0] / length : (v1 - v0 > 1 ? double(v - v0) / (v1 - v0 - 1) : 0.0);
            parts.vertexLocalW[v] = float(std::clamp(t, 0.0, 1.0) * span);
            parts.vertexFirstPart[v] = first;
        }
        if (v1 > v0) parts.vertexLocalW[v1 - 1] = span;  // exactly, so frac(w) = 0 at the end
    }
    parts.firstPart[lines] = std::uint32_t(lines * std::size_t(partsPerLine));
    return parts;
}

std::vector<double> partImportance(const OpacityParts& parts, const std::vector<glm::vec3>& positions,
                                   const std::vector<std::uint32_t>& offsets, const OpacityOptimizationSpec& spec,
                                   const std::vector<float>* attribute) {
    using Kind = OpacityOptimizationSpec::Importance;
    const std::size_t n = parts.partCount();
    const std::size_t lines = parts.polylineCount();
    const int m = parts.partsPerLine;
    std::vector<double> g(n, 0.5);
    if (spec.importance == Kind::Constant) return g;

    if (spec.importance == Kind::Length) {
        std::vector<double> length(lines, 0.0);
        double longest = 0;
        for (std::size_t l = 0; l < lines; ++l) {
            for (std::uint32_t v = offsets[l] + 1; v < offsets[l + 1]; ++v)
                length[l] += glm::distance(positions[v - 1], positions[v]);
            longest = std::max(longest, length[l]);
        }
        for (std::size_t l = 0; l < lines; ++l)
            for (int k = 0; k < m; ++k) g[parts.firstPart[l] + k] = longest > 0 ? length[l] / longest : 0.0;
        return g;
    }

    if (spec.importance == Kind::Curvature) {
        std::fill(g.begin(), g.end(), 0.0);
        for (std::size_t l = 0; l < lines; ++l) {
            for (std::uint32_t v = offsets[l] + 1; v + 1 < offsets[l + 1]; ++v) {
                const glm::dvec3 a = glm::dvec3(positions[v]) - glm::dvec3(positions[v - 1]);
                const glm::dvec3 b = glm::dvec3(positions[v + 1]) - glm::dvec3(positions[v]);
                const double la = glm::length(a), lb = glm::length(b);
                if (la <= 0 || lb <= 0) continue;
                const double turning = std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
                g[parts.firstPart[l] + std::uint32_t(std::lround(parts.vertexLocalW[v]))] += turning;
            }
        }
        const double largest = *std::max_element(g.begin(), g.end());
        for (double& x : g) x = largest > 0 ? x / largest : 0.0;
        return g;
    }

    // Attribute: arc-length weighted mean over each part's interval of t.
    TC_CHECK(attribute != nullptr && attribute->size() == positions.size());
    const double lo = spec.rangeLo, scale = 1.0 / double(spec.rangeHi - spec.rangeLo);
    std::vector<double> integral(n, 0.0), weight(n, 0.0);
    for (std::size_t l = 0; l < lines; ++l) {
        const std::uint32_t first = parts.firstPart[l];
        const std::uint32_t v0 = offsets[l], v1 = offsets[l + 1];
        auto value = [&](std::uint32_t v) {
            float x = (*attribute)[v];
            return std::isnan(x) ? lo : double(x);
        };
        if (v1 - v0 == 1 || m == 1) {  // one part: the plain arc-length mean over the polyline
            for (std::uint32_t v = v0 + 1; v < v1; ++v) {
                const double len = glm::distance(positions[v - 1], positions[v]);
                integral[first] += len * 0.5 * (value(v - 1) + value(v));
                weight[first] += len;
            }
            if (weight[first] == 0) {
                integral[first] = value(v0);
                weight[first] = 1;
            }
            for (int k = 1; k < m; ++k) {
                integral[first + k] = integral[first];
                weight[first + k] = weight[first];
            }
            continue;
        }
        // In local w units part k covers [k - 1/2, k + 1/2] clipped to [0, m - 1].
        for (std::uint32_t v = v0 + 1; v < v1; ++v) {
            const double wa = parts.vertexLocalW[v - 1], wb = parts.vertexLocalW[v];
            if (!(wb > wa)) continue;
            const double fa = value(v - 1), fb = value(v);
            const int kLo = std::max(0, int(std::floor(wa - 0.5))), kHi = std::min(m - 1, int(std::ceil(wb + 0.5)));
            for (int k = kLo; k <= kHi; ++k) {
                const double a = std::max(wa, k - 0.5), b = std::min(wb, k + 0.5);
                if (!(b > a)) continue;
                const double mid = 0.5 * (a + b);
                const double f = fa + (fb - fa) * (mid - wa) / (wb - wa);  // linear: midpoint rule is exact
                integral[first + k] += (b - a) * f;
                weight[first + k] += b - a;
            }
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const double mean = weight[i] > 0 ? integral[i] / weight[i] : lo;
        g[i] = std::clamp((mean - lo) * scale, 0.0, 1.0);
    }
    return g;
}

void SparseQpOperator::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    multiplyRows(m_q, x, y);
}

namespace {

bool keptBy(double v, double dropBelow) {
    return v != 0 && !(v < dropBelow);
}

// H in single precision, zeros and entries below dropBelow (compared in double) left out.
SparseMatrixF toSingle(const SparseMatrixD& h, double dropBelow) {
    SparseMatrixF out(h.rows(), h.cols());
    out.reserve(h.nonZeros());
    for (Eigen::Index i = 0; i < h.outerSize(); ++i) {
        out.startVec(i);
        for (SparseMatrixD::InnerIterator it(h, i); it; ++it)
            if (keptBy(it.value(), dropBelow)) out.insertBack(i, it.index()) = float(it.value());
    }
    out.finalize();
    return out;
}

}  // namespace

OpacityEnergy::OpacityEnergy(const SparseMatrixD& h, const std::vector<double>& g, const OpacityParts& parts,
                             const OpacityWeights& weights, double dropBelow)
    : OpacityEnergy(toSingle(h, dropBelow), g, parts, weights) {
    for (Eigen::Index i = 0; i < h.outerSize(); ++i)
        for (SparseMatrixD::InnerIterator it(h, i); it; ++it) m_dropped += it.value() != 0 && it.value() < dropBelow;
}

OpacityEnergy::OpacityEnergy(SparseMatrixF&& h, const std::vector<double>& g, const OpacityParts& parts,
                             const OpacityWeights& weights, double dropBelow)
    : m_n(Eigen::Index(parts.partCount())),
      m_weights(weights),
      m_partsPerLine(parts.partsPerLine),
      m_firstPart(parts.firstPart) {
    TC_CHECK_OP(h.rows(), ==, m_n);
    TC_CHECK_OP(h.cols(), ==, m_n);
    // Eigen 3.4's SparseMatrix has no move constructor (std::move would copy); swap is O(1).
    m_h.swap(h);
    setScales(g);
    m_h.makeCompressed();  // in place; occlusionMatrix's H is compressed already
    if (dropBelow > 0) {
        // In place, rows ascending (Eigen's prune compacts without reallocating).
        std::size_t dropped = 0;
        m_h.prune([&](Eigen::Index, Eigen::Index, float v) {
            dropped += v != 0 && double(v) < dropBelow;
            return keptBy(double(v), dropBelow);
        });
        m_dropped = dropped;
    }
    setUpFromH(parts);
}

void OpacityEnergy::releaseOcclusion(SparseMatrixF& into) {
    into.swap(m_h);
    m_h.resize(m_n, m_n);  // empty: products skip the occlusion terms
    m_rowChunks.assign({0, int(m_n)});
}

void OpacityEnergy::setUpFromH(const OpacityParts& parts) {
    // H is taken over as it is (occlusionMatrix builds it in this form), not copied: copying a
    // double H into this one took 13-30 ms of an 8k-part warm frame's 80-100 ms solve stage
    // (`FRAMES=8 SIZES="8000:assembled:1" scripts/bench/opacity_tables.sh`; the set-up alone:
    // `tubecast_fragment_occlusion_bench FILE --assembled 1`). What is left reads H twice, in
    // parallel, and sums in the order of serial loops (so the diagonal is bit-identical to theirs).
    const int* outer = m_h.outerIndexPtr();
    const int* inner = m_h.innerIndexPtr();
    const float* value = m_h.valuePtr();
    const bool parallel = m_h.nonZeros() >= 20000;
    const int threads = tbb::this_task_arena::max_concurrency();

    // diag(W W^T)_i = R_i^2 sum_j h_ij^2 C_j^2, diag(V V^T)_i = R_i^2 sum_j h_ji^2 C_j^2.
    Eigen::VectorXd rowSum(m_n), colSum = Eigen::VectorXd::Zero(m_n);
    auto rowRange = [&](Eigen::Index i0, Eigen::Index i1) {
        for (Eigen::Index i = i0; i < i1; ++i) {
            double sum = 0;
            for (int k = outer[i]; k < outer[i + 1]; ++k) {
                const double v = double(value[k]);
                sum += v * v * m_colScale2[inner[k]];
            }
            rowSum[i] = sum;
        }
    };
    if (parallel)
        tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, m_n, 256),
                          [&](const auto& r) { rowRange(r.begin(), r.end()); });
    else
        rowRange(0, m_n);

    // Row ranges of about equal work; a few per thread so a thread slowed by other processes
    // does not hold the pass up.
    const int chunks = m_h.nonZeros() < 20000 ? 1 : std::max(1, 2 * threads);
    m_rowChunks.assign(1, 0);
    for (int c = 1; c < chunks; ++c) {
        const std::int64_t target = std::int64_t(m_h.nonZeros()) * c / chunks;
        const int row = int(std::lower_bound(outer, outer + m_n, target) - outer);
        if (row > m_rowChunks.back() && row < m_n) m_rowChunks.push_back(row);
    }
    m_rowChunks.push_back(int(m_n));

    // The column sums in parallel over column ranges, each walking the rows in order (its part of
    // each row found by binary search: columns are sorted), so every column still sums its rows
    // in ascending order.
    auto columnRange = [&](int c0, int c1) {
        for (Eigen::Index i = 0; i < m_n; ++i) {
            const int* first = inner + outer[i];
            const int* last = inner + outer[i + 1];
            if (c0 > 0) first = std::lower_bound(first, last, c0);
            const double scale = m_colScale2[i];
            for (const int* k = first; k != last && *k < c1; ++k) {
                const double v = double(value[k - inner]);
                colSum[*k] += v * v * scale;
            }
        }
    };
    const int columnRanges = parallel ? std::max(1, 2 * threads) : 1;
    if (columnRanges == 1)
        columnRange(0, int(m_n));
    else
        tbb::parallel_for(0, columnRanges,
                          [&](int c) { columnRange(int(m_n * c / columnRanges), int(m_n * (c + 1) / columnRanges)); });
    setDiagonal(rowSum, colSum, parts);
}

OpacityEnergy::OpacityEnergy(std::shared_ptr<const FragmentOcclusion> occlusion, const std::vector<double>& g,
                             const OpacityParts& parts, const OpacityWeights& weights, double squareEstimate)
    : m_n(Eigen::Index(parts.partCount())),
      m_weights(weights),
      m_fragments(std::move(occlusion)),
      m_partsPerLine(parts.partsPerLine),
      m_firstPart(parts.firstPart) {
    TC_CHECK(m_fragments != nullptr);
    TC_CHECK_OP(Eigen::Index(m_fragments->partCount()), ==, m_n);
    setScales(g);
    m_h.resize(m_n, m_n);
    // The squared sums of diag(Q) estimated from one pass: sum_j h_ij^2 c_j ~= k sum_j h_ij c_j,
    // k = squareEstimate. Exact when every non-zero h_ij equals k; an upper bound for k = 1 while
    // h <= 1. Only the preconditioner sees it (k chosen at 8k parts with `tubecast_opacity_bench
    // --parts 8000 --occlusion fragments --square-estimate K`).
    Eigen::VectorXd rowSum, colSum;
    m_fragments->multiply(&m_colScale2, &rowSum, &m_colScale2, &colSum);
    setDiagonal(squareEstimate * rowSum, squareEstimate * colSum, parts);
}

void OpacityEnergy::setScales(const std::vector<double>& g) {
    TC_CHECK_OP(Eigen::Index(g.size()), ==, m_n);
    // (I - G)^lambda with 0^0 = 1: lambda = 0 leaves the unimportant-first weighting out.
    m_rowScale.resize(m_n);
    m_colScale2.resize(m_n);
    for (Eigen::Index i = 0; i < m_n; ++i) {
        m_rowScale[i] = std::pow(std::max(0.0, 1.0 - g[i]), m_weights.lambda);
        m_colScale2[i] = g[i] * g[i];
    }
}

void OpacityEnergy::setDiagonal(const Eigen::VectorXd& rowSum, const Eigen::VectorXd& colSum,
                                const OpacityParts& parts) {
    // diag(D^T D)_i = the number of neighbours of part i on its polyline.
    m_diagonal.resize(m_n);
    const int m = parts.partsPerLine;
    for (std::size_t l = 0; l < parts.polylineCount(); ++l)
        for (int k = 0; k < m; ++k) {
            const Eigen::Index i = parts.firstPart[l] + k;
            const double r2 = m_rowScale[i] * m_rowScale[i];
            const int neighbours = (k > 0) + (k + 1 < m);
            m_diagonal[i] = 2.0 * (m_weights.p + m_weights.q * r2 * rowSum[i] + m_weights.r * r2 * colSum[i] +
                                   m_weights.s * neighbours);
        }
}

void OpacityEnergy::multiplyBoth(const Eigen::VectorXd& xg, const Eigen::VectorXd& xs, Eigen::VectorXd* hx,
                                 Eigen::VectorXd* htx) const {
    if (m_fragments) {
        m_fragments->multiply(&xg, hx, &xs, htx);
        return;
    }
    const int* outer = m_h.outerIndexPtr();
    const int* inner = m_h.innerIndexPtr();
    const float* value = m_h.valuePtr();
    const int chunks = int(m_rowChunks.size()) - 1;
    if (hx) hx->resize(m_n);
    // H^T xs scatters into columns: each chunk into its own buffer, summed afterwards (no atomics;
    // n doubles per chunk stay in cache up to ~100k parts).
    std::vector<Eigen::VectorXd> scatter(htx ? std::size_t(chunks) : 0);
    const auto body = [&](int c) {
        double* out = nullptr;
        if (htx) {
            scatter[c].setZero(m_n);
            out = scatter[c].data();
        }
        for (int row = m_rowChunks[c]; row < m_rowChunks[c + 1]; ++row) {
            const int begin = outer[row], end = outer[row + 1];
            if (hx && out) {
                double sum = 0;
                const double s = xs[row];
                for (int k = begin; k < end; ++k) {
                    sum += double(value[k]) * xg[inner[k]];
                    out[inner[k]] += double(value[k]) * s;
                }
                (*hx)[row] = sum;
            } else if (hx) {
                double sum = 0;
                for (int k = begin; k < end; ++k) sum += double(value[k]) * xg[inner[k]];
                (*hx)[row] = sum;
            } else {
                const double s = xs[row];
                if (s != 0)
                    for (int k = begin; k < end; ++k) out[inner[k]] += double(value[k]) * s;
            }
        }
    };
    if (chunks == 1)
        body(0);
    else
        tbb::parallel_for(0, chunks, body);
    if (htx) {
        *htx = std::move(scatter[0]);
        for (int c = 1; c < chunks; ++c) *htx += scatter[c];
    }
}

void OpacityEnergy::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    // Q x = 2(p x + q R H C^2 H^T R x + r R H^T C^2 H R x + s D^T D x). The element-wise steps
    // run in chunks (core/parallel_chunks.h), each in the order of the serial expressions they
    // replaced.
    y.resize(m_n);
    const bool wTerm = m_weights.q != 0, vTerm = m_weights.r != 0;
    const bool occlusion = (wTerm || vTerm) && (m_fragments || m_h.nonZeros() > 0);
    Eigen::VectorXd u, hu, htu, a, b;
    if (occlusion) {
        u.resize(m_n);
        forChunks(m_n, [&](std::int64_t i0, std::int64_t i1) {
            for (std::int64_t i = i0; i < i1; ++i) u[i] = m_rowScale[i] * x[i];
        });
        multiplyBoth(u, u, vTerm ? &hu : nullptr, wTerm ? &htu : nullptr);
        // Second pass: gather H (C^2 H^T u) for the W term, scatter H^T (C^2 H u) for the V term.
        forChunks(m_n, [&](std::int64_t i0, std::int64_t i1) {
            for (std::int64_t i = i0; i < i1; ++i) {
                if (wTerm) htu[i] *= m_colScale2[i];
                if (vTerm) hu[i] *= m_colScale2[i];
            }
        });
        multiplyBoth(wTerm ? htu : u, vTerm ? hu : u, wTerm ? &a : nullptr, vTerm ? &b : nullptr);
    }
    const double p = m_weights.p, q = m_weights.q, r = m_weights.r, s = m_weights.s;
    const int m = m_partsPerLine;
    // Polylines in chunks (a polyline's parts are [firstPart[l], firstPart[l] + m)).
    const std::int64_t lines = std::int64_t(m_firstPart.size()) - 1;
    forChunks(
        lines,
        [&](std::int64_t l0, std::int64_t l1) {
            for (std::int64_t l = l0; l < l1; ++l) {
                const Eigen::Index first = m_firstPart[std::size_t(l)];
                for (int k = 0; k < m; ++k) {
                    const Eigen::Index i = first + k;
                    double v = p * x[i];
                    if (occlusion && wTerm) v += q * (m_rowScale[i] * a[i]);
                    if (occlusion && vTerm) v += r * (m_rowScale[i] * b[i]);
                    if (s != 0) {
                        if (k > 0) v -= s * (x[i - 1] - x[i]);
                        if (k + 1 < m) v += s * (x[i] - x[i + 1]);
                    }
                    y[i] = 2.0 * v;
                }
            }
        },
        kVectorChunk / m);
}

bool OpacityEnergy::precondition(const Eigen::VectorXd& r, const std::vector<char>& isFree, Eigen::VectorXd& z) const {
    z.resize(m_n);
    const double off = -2.0 * m_weights.s;
    const std::int64_t lines = std::int64_t(m_firstPart.size()) - 1;
    // Polylines are independent: in chunks (core/parallel_chunks.h), each writing its own parts.
    forChunks(
        lines,
        [&](std::int64_t l0, std::int64_t l1) {
            std::vector<double> cPrime(static_cast<std::size_t>(m_partsPerLine)), dPrime(cPrime.size());
            for (std::int64_t l = l0; l < l1; ++l) {
                const Eigen::Index first = m_firstPart[std::size_t(l)], end = first + m_partsPerLine;
                for (Eigen::Index k0 = first; k0 < end;) {
                    if (!isFree[std::size_t(k0)]) {
                        z[k0] = 0;
                        ++k0;
                        continue;
                    }
                    Eigen::Index k1 = k0;  // the run [k0, k1) of free parts
                    while (k1 < end && isFree[std::size_t(k1)]) ++k1;
                    // Thomas algorithm; diagonally dominant (diag >= 2(p + s deg) > |off| deg), so stable.
                    for (Eigen::Index k = k0; k < k1; ++k) {
                        const std::size_t t = std::size_t(k - k0);
                        const double m = m_diagonal[k] - (t ? off * cPrime[t - 1] : 0.0);
                        cPrime[t] = off / m;
                        dPrime[t] = (r[k] - (t ? off * dPrime[t - 1] : 0.0)) / m;
                    }
                    for (Eigen::Index k = k1 - 1; k >= k0; --k) {
                        const std::size_t t = std::size_t(k - k0);
                        z[k] = dPrime[t] - (k + 1 < k1 ? cPrime[t] * z[k + 1] : 0.0);
                    }
                    k0 = k1;
                }
            }
        },
        kVectorChunk / m_partsPerLine);
    return true;
}

double OpacityEnergy::energy(const Eigen::VectorXd& a) const {
    double e = m_weights.p * (a - Eigen::VectorXd::Ones(m_n)).squaredNorm();
    // |W^T a|^2 = |C H^T R a|^2, |V^T a|^2 = |C H R a|^2.
    Eigen::VectorXd hu, htu;
    multiplyBoth(m_rowScale.cwiseProduct(a), m_rowScale.cwiseProduct(a), &hu, &htu);
    e += m_weights.q * htu.cwiseAbs2().dot(m_colScale2);
    e += m_weights.r * hu.cwiseAbs2().dot(m_colScale2);
    forEachNeighbourPair([&](Eigen::Index i) { e += m_weights.s * (a[i + 1] - a[i]) * (a[i + 1] - a[i]); });
    return e;
}

SparseMatrixD OpacityEnergy::assemble() const {
    TC_CHECK(!m_fragments);  // H from the fragment lists is never assembled
    Eigen::VectorXd colScale = m_colScale2.cwiseSqrt();
    const SparseMatrixD h = m_h.cast<double>();
    const SparseMatrixD ht = h.transpose();
    const SparseMatrixD w = m_rowScale.asDiagonal() * h * colScale.asDiagonal();
    const SparseMatrixD v = m_rowScale.asDiagonal() * ht * colScale.asDiagonal();
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::Index rows = 0;
    forEachNeighbourPair([&](Eigen::Index i) {
        triplets.emplace_back(rows, i, -1.0);
        triplets.emplace_back(rows++, i + 1, 1.0);
    });
    SparseMatrixD d(rows, m_n);
    d.setFromTriplets(triplets.begin(), triplets.end());
    SparseMatrixD identity(m_n, m_n);
    identity.setIdentity();
    const SparseMatrixD wwt = w * SparseMatrixD(w.transpose()), vvt = v * SparseMatrixD(v.transpose());
    const SparseMatrixD dtd = SparseMatrixD(d.transpose()) * d;
    SparseMatrixD q = 2.0 * (m_weights.p * identity + m_weights.q * wwt + m_weights.r * vvt + m_weights.s * dtd);
    q.prune(0.0);
    return q;
}

SparsificationBound sparsificationBound(const QpOperator& exact, const QpOperator& sparsified,
                                        const Eigen::VectorXd& solution, double mu) {
    TC_CHECK(mu > 0);
    Eigen::VectorXd qa, qa2;
    exact.multiply(solution, qa);
    sparsified.multiply(solution, qa2);
    SparsificationBound b;
    b.delta = (qa - qa2).norm();
    b.distance = b.delta / mu;
    b.objective = b.delta * b.delta / mu;
    return b;
}

double projectedGradientNorm(const Eigen::VectorXd& gradient, const Eigen::VectorXd& x, const Eigen::VectorXd& lo,
                             const Eigen::VectorXd& hi) {
    if (x.size() == 0) return 0;
    return projectedGradient(gradient, x, lo, hi).lpNorm<Eigen::Infinity>();
}

namespace {

// Partial results of the solver's chunked passes (core/parallel_chunks.h) and how two are joined.
struct MaxSum {
    double sum = 0, max = 0;
};
struct TwoSums {
    double a = 0, b = 0;
};
constexpr auto joinMaxSum = [](MaxSum a, MaxSum b) { return MaxSum{a.sum + b.sum, std::max(a.max, b.max)}; };
constexpr auto maxOf = [](double a, double b) { return std::max(a, b); };
constexpr auto joinTwoSums = [](TwoSums u, TwoSums v) { return TwoSums{u.a + v.a, u.b + v.b}; };

// solveBoundedQp's iteration (see its comment in the header): the iterate, its gradient and the
// work vectors, and one method per step of an outer iteration. The vector work runs in fixed
// chunks (core/parallel_chunks.h): serial, it cost 10-18 % of a 128k-part solve's wall time (A/B
// in docs/performance.md, opacity optimization).
class BoundedQpSolver {
public:
    BoundedQpSolver(const QpOperator& q, const Eigen::VectorXd& c, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                    const Eigen::VectorXd& x0, const QpSolverOptions& options);
    QpResult solve();

private:
    // How a projected line search ended (projectedSearch).
    enum class Search { Failed, Accepted, Breakpoint };

    double steepestDescentDirection();
    bool faceSettled() const;
    void gradientProjectionStep();
    bool subspaceStep(bool binding);
    TwoSums selectFreeVariables(bool binding);
    void truncatedCg(bool binding, double r0);
    void subspaceSearch(bool binding);
    Search projectedSearch(const Eigen::VectorXd& dir, const Eigen::VectorXd& qdir, double step, bool toBreakpoint);
    Search cutAtBreakpoint(const Eigen::VectorXd& dir, const Eigen::VectorXd& qdir, double step);
    void acceptStep();
    void precondition(const Eigen::VectorXd& residual, Eigen::VectorXd& out) const;
    char state(Eigen::Index i) const { return char(m_x[i] <= m_lo[i] ? 0 : m_x[i] >= m_hi[i] ? 2 : 1); }
    void finish();

    static constexpr double kArmijo = 1e-4;
    static constexpr int kMaxBacktracks = 40;

    const QpOperator& m_q;
    const Eigen::VectorXd& m_c;
    const Eigen::VectorXd& m_lo;
    const Eigen::VectorXd& m_hi;
    const QpSolverOptions& m_options;
    const Eigen::Index m_n;
    QpResult m_result;
    Eigen::VectorXd m_x, m_qx, m_g;  // the iterate, Q x and the gradient Q x + c
    Eigen::VectorXd m_d, m_qd;       // a step's direction and Q d
    Eigen::VectorXd m_y, m_s, m_qs;  // a search's trial point, s = y - x and Q s
    Eigen::VectorXd m_inverseDiagonal;
    Eigen::VectorXd m_r, m_z, m_p, m_qp;  // CG: residual, preconditioned residual, direction, Q p
    std::vector<char> m_isFree, m_stateBefore;
    bool m_forceGradientStep = false;
    Eigen::Index m_lastChanges = -1;  // variables whose state (at lo, free, at hi) the last CG step changed
};

BoundedQpSolver::BoundedQpSolver(const QpOperator& q, const Eigen::VectorXd& c, const Eigen::VectorXd& lo,
                                 const Eigen::VectorXd& hi, const Eigen::VectorXd& x0, const QpSolverOptions& options)
    : m_q(q), m_c(c), m_lo(lo), m_hi(hi), m_options(options), m_n(q.size()) {
    TC_CHECK_OP(c.size(), ==, m_n);
    TC_CHECK_OP(lo.size(), ==, m_n);
    TC_CHECK_OP(hi.size(), ==, m_n);
    TC_CHECK_OP(x0.size(), ==, m_n);
    m_x = clampBox(x0, lo, hi);
    q.multiply(m_x, m_qx);
    ++m_result.products;
    m_g = m_qx + c;
    const Eigen::VectorXd diagonal = q.diagonal();
    m_inverseDiagonal = diagonal.cwiseMax(1e-300).cwiseInverse();
    m_d.resize(m_n);
    m_qd.resize(m_n);
    m_r.resize(m_n);
    m_z.resize(m_n);
    m_p.resize(m_n);
    m_qp.resize(m_n);
    m_isFree.assign(std::size_t(m_n), 0);
    m_stateBefore.assign(std::size_t(m_n), 0);
}

QpResult BoundedQpSolver::solve() {
    for (;; ++m_result.iterations) {
        m_result.residual = steepestDescentDirection();
        if (m_result.residual <= m_options.tolerance) {
            m_result.converged = true;
            break;
        }
        if (m_result.iterations >= m_options.maxIterations) break;
        // 1. A projected steepest-descent step to change the active face, unless it is settled.
        // With the binding set, CG below runs on the binding variables unless this iteration
        // was forced to take the gradient step.
        const bool settled = faceSettled();
        const bool binding = m_options.bindingSet && !m_forceGradientStep;
        m_forceGradientStep = false;
        if (!settled) gradientProjectionStep();
        // 2. Truncated PCG on the free variables and a projected search along its step. Without
        // free variables (or with r = 0 on them) the next iteration takes the gradient step.
        if (!subspaceStep(binding)) m_forceGradientStep = true;
    }
    finish();
    return std::move(m_result);
}

// d = -(projected gradient); returns its max norm (the KKT residual).
double BoundedQpSolver::steepestDescentDirection() {
    return reduceChunks(
        m_n, 0.0,
        [&](std::int64_t b, std::int64_t e, double& m) {
            for (std::int64_t i = b; i < e; ++i) {
                const double pg = projectedComponent(m_g[i], m_x[i], m_lo[i], m_hi[i]);
                m_d[i] = -pg;
                m = std::max(m, std::abs(pg));
            }
        },
        maxOf);
}

// The gradient step is taken with the binding set only when the last CG step found no decrease
// (m_forceGradientStep). Without it, it is skipped when no variable at a bound wants to leave it
// (the projected gradient lives on the free variables): then the face is right and CG does better
// with the product (the usual case near the solution, e.g. warm started).
bool BoundedQpSolver::faceSettled() const {
    bool settled = !m_forceGradientStep;
    if (!m_options.bindingSet)
        for (Eigen::Index i = 0; i < m_n && settled; ++i)
            if (!(m_x[i] > m_lo[i] && m_x[i] < m_hi[i]) && m_d[i] != 0) settled = false;
    return settled;
}

// Projected steepest descent along d, starting from the exact minimiser along d (g.d = -|d|^2).
void BoundedQpSolver::gradientProjectionStep() {
    if (m_options.scaledGradientStep) m_d = m_d.cwiseProduct(m_inverseDiagonal);
    m_q.multiply(m_d, m_qd);
    ++m_result.products;
    const double curvature = m_d.dot(m_qd), slope = -m_g.dot(m_d);  // slope = |d|^2 unscaled
    projectedSearch(m_d, m_qd, curvature > 0 ? slope / curvature : 1.0, curvature > 0);
}

// False when there is nothing for CG to do (no free variable, or r = 0 on them).
bool BoundedQpSolver::subspaceStep(bool binding) {
    const TwoSums start = selectFreeVariables(binding);
    const double r0 = std::sqrt(start.a);
    if (start.b == 0 || r0 == 0) return false;
    truncatedCg(binding, r0);
    subspaceSearch(binding);
    return true;
}

// The free variables: those inside the box, and with the binding set also those at a bound whose
// gradient points into the box (they may leave it). r = -g on them, 0 elsewhere. Returns |r|^2
// and the free count.
TwoSums BoundedQpSolver::selectFreeVariables(bool binding) {
    return reduceChunks(
        m_n, TwoSums{},
        [&](std::int64_t b, std::int64_t e, TwoSums& m) {
            for (std::int64_t i = b; i < e; ++i) {
                const bool inside = m_x[i] > m_lo[i] && m_x[i] < m_hi[i];
                m_isFree[i] =
                    inside || (binding && ((m_x[i] <= m_lo[i] && m_g[i] < 0) || (m_x[i] >= m_hi[i] && m_g[i] > 0)));
                m_r[i] = m_isFree[i] ? -m_g[i] : 0.0;
                m.a += m_r[i] * m_r[i];
                m.b += m_isFree[i];  // the free count
            }
        },
        joinTwoSums);
}

// Preconditioned CG on the free variables from d = 0, r0 = |r|: d becomes the step, qd = Q d.
void BoundedQpSolver::truncatedCg(bool binding, double r0) {
    // Forcing term min(0.1, sqrt|r0|): loose far away, tight near the solution; and no further
    // than the stopping test needs (its max norm well under the tolerance): going on costs
    // products and buys digits nobody asked for. With the binding set, once the last step changed
    // the state of at most 1 % of the variables the face is nearly found, and 0.01 saves outer
    // iterations (each costs a clipped step's product).
    const bool faceNearlyFound = binding && m_lastChanges >= 0 && 100 * m_lastChanges <= m_n;
    const double stop = (faceNearlyFound ? 0.01 : std::min(0.1, std::sqrt(r0))) * r0;
    const double stopMax = 0.25 * m_options.tolerance;
    precondition(m_r, m_z);
    forChunks(m_n, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t i = b; i < e; ++i) {
            m_p[i] = m_z[i];
            m_d[i] = 0;
            m_qd[i] = 0;
        }
    });
    double rz = sumChunks(m_n, [&](std::int64_t i) { return m_r[i] * m_z[i]; });
    for (int k = 0; k < m_options.maxCgIterations; ++k) {
        m_q.multiply(m_p, m_qp);
        ++m_result.products;
        ++m_result.cgIterations;
        const double pqp = sumChunks(m_n, [&](std::int64_t i) { return m_isFree[i] ? m_p[i] * m_qp[i] : 0.0; });
        if (!(pqp > 0)) break;
        const double alpha = rz / pqp;
        const MaxSum rest = reduceChunks(
            m_n, MaxSum{},
            [&](std::int64_t b, std::int64_t e, MaxSum& m) {
                for (std::int64_t i = b; i < e; ++i) {
                    m_d[i] += alpha * m_p[i];
                    m_qd[i] += alpha * m_qp[i];
                    if (m_isFree[i]) m_r[i] -= alpha * m_qp[i];
                    m.sum += m_r[i] * m_r[i];
                    m.max = std::max(m.max, std::abs(m_r[i]));
                }
            },
            joinMaxSum);
        if (std::sqrt(rest.sum) <= stop || rest.max <= stopMax) break;
        // With the binding set, while the face is still far from found: once the CG iterate has
        // left the box (from the second iteration on), the search will clip it and change the
        // face anyway, and further CG iterations on this face are wasted products. From a poor
        // start (a Jacobi step from a = 1) a 128k-part cold solve took 192 products without this
        // and 42 with it; from a = 1, 35-36 instead of 37-38.
        if (binding && !faceNearlyFound && k >= 1) {
            const double outside = sumChunks(m_n, [&](std::int64_t i) {
                return m_isFree[i] && (m_x[i] + m_d[i] < m_lo[i] || m_x[i] + m_d[i] > m_hi[i]) ? 1.0 : 0.0;
            });
            if (outside > 0) break;
        }
        precondition(m_r, m_z);
        const double rzNext = sumChunks(m_n, [&](std::int64_t i) { return m_r[i] * m_z[i]; });
        const double beta = rzNext / rz;
        forChunks(m_n, [&](std::int64_t b, std::int64_t e) {
            for (std::int64_t i = b; i < e; ++i) m_p[i] = m_z[i] + beta * m_p[i];
        });
        rz = rzNext;
    }
}

// The projected search along the CG step d, and what it means for the next iteration.
void BoundedQpSolver::subspaceSearch(bool binding) {
    if (m_options.bindingSet)  // for m_lastChanges, which only the binding set reads
        forChunks(m_n, [&](std::int64_t b, std::int64_t e) {
            for (std::int64_t i = b; i < e; ++i) m_stateBefore[i] = state(i);
        });
    // Without the binding set a failed search forces the gradient step. With it, so does a step
    // cut at the first bound: it changes one variable, and repeating it can take one iteration
    // per variable that must reach a bound (seen from a poor start at 32k parts).
    const Search search = projectedSearch(m_d, m_qd, 1.0, true);
    if (search == Search::Failed || (binding && search == Search::Breakpoint)) m_forceGradientStep = true;
    m_lastChanges =
        !m_options.bindingSet || search != Search::Accepted
            ? -1
            : Eigen::Index(sumChunks(m_n, [&](std::int64_t i) { return m_stateBefore[i] != state(i) ? 1.0 : 0.0; }));
}

// Moves x to P(x + step * dir) with Armijo backtracking on step; qdir = Q dir saves a product
// whenever no component is clipped. With `toBreakpoint` (the quadratic along the ray x + t dir is
// smallest at t >= `step`: true for the steepest-descent step at its exact minimiser and for a CG
// step on the free face), a clipped step that fails is not halved (a product per trial; these were
// half of all products at 8k parts) but cut to the first bound the ray meets (cutAtBreakpoint).
// Failed: no decrease found.
BoundedQpSolver::Search BoundedQpSolver::projectedSearch(const Eigen::VectorXd& dir, const Eigen::VectorXd& qdir,
                                                         double step, bool toBreakpoint) {
    m_y.resize(m_n);
    m_s.resize(m_n);
    m_qs.resize(m_n);
    for (int k = 0; k < kMaxBacktracks; ++k, step *= 0.5) {
        // y = P(x + step dir), s = y - x; clipped when some component left the box.
        const double clip = reduceChunks(
            m_n, 0.0,
            [&](std::int64_t b, std::int64_t e, double& m) {
                for (std::int64_t i = b; i < e; ++i) {
                    m_y[i] = std::clamp(m_x[i] + step * dir[i], m_lo[i], m_hi[i]);
                    m_s[i] = m_y[i] - m_x[i];
                    m = std::max(m, std::abs(m_s[i] - step * dir[i]));
                }
            },
            maxOf);
        const bool clipped = clip > 0;
        if (clipped) {
            m_q.multiply(m_s, m_qs);
            ++m_result.products;
            ++m_result.searchProducts;
        } else {
            forChunks(m_n, [&](std::int64_t b, std::int64_t e) {
                for (std::int64_t i = b; i < e; ++i) m_qs[i] = step * qdir[i];
            });
        }
        // g.s and s.Q s in one pass.
        const TwoSums dots = reduceChunks(
            m_n, TwoSums{},
            [&](std::int64_t b, std::int64_t e, TwoSums& m) {
                for (std::int64_t i = b; i < e; ++i) {
                    m.a += m_g[i] * m_s[i];
                    m.b += m_s[i] * m_qs[i];
                }
            },
            joinTwoSums);
        const double gs = dots.a, sqs = dots.b;
        if (gs < 0 && gs + 0.5 * sqs <= kArmijo * gs) {
            acceptStep();
            return Search::Accepted;
        }
        if (clipped && toBreakpoint) return cutAtBreakpoint(dir, qdir, step);
    }
    return Search::Failed;
}

// The step to the first bound the ray x + t dir meets, t < `step`: it needs no product and
// decreases the objective, the quadratic being convex along the ray.
BoundedQpSolver::Search BoundedQpSolver::cutAtBreakpoint(const Eigen::VectorXd& dir, const Eigen::VectorXd& qdir,
                                                         double step) {
    double breakpoint = step;
    Eigen::Index first = -1;
    for (Eigen::Index i = 0; i < m_n; ++i) {
        const double t = dir[i] > 0 ? (m_hi[i] - m_x[i]) / dir[i] : dir[i] < 0 ? (m_lo[i] - m_x[i]) / dir[i] : step;
        if (t < breakpoint) {
            breakpoint = t;
            first = i;
        }
    }
    if (!(breakpoint > 0) || first < 0) return Search::Failed;
    m_y = clampBox(m_x + breakpoint * dir, m_lo, m_hi);
    m_y[first] = dir[first] > 0 ? m_hi[first] : m_lo[first];  // exactly on the bound it reached
    m_s = m_y - m_x;
    const double gb = m_g.dot(m_s);
    if (!(gb < 0)) return Search::Failed;
    m_qs = breakpoint * qdir;  // s = breakpoint * dir up to rounding
    acceptStep();
    return Search::Breakpoint;
}

// x = y; Q x and the gradient follow with Q s.
void BoundedQpSolver::acceptStep() {
    forChunks(m_n, [&](std::int64_t b, std::int64_t e) {
        for (std::int64_t i = b; i < e; ++i) {
            m_x[i] = m_y[i];
            m_qx[i] += m_qs[i];
            m_g[i] = m_qx[i] + m_c[i];
        }
    });
}

void BoundedQpSolver::precondition(const Eigen::VectorXd& residual, Eigen::VectorXd& out) const {
    if (!m_q.precondition(residual, m_isFree, out)) out = m_inverseDiagonal.cwiseProduct(residual);
}

// The residual of the loop uses the running gradient, updated with the exact Q s of every step
// (its drift from Q x + c is rounding; tubecast_opacity_bench prints both). A converged solve
// keeps it (a product is 1/12 of a warm solve); one that ran out of iterations recomputes it from
// scratch, so the value in the warning is the true one.
void BoundedQpSolver::finish() {
    if (!m_result.converged) {
        m_q.multiply(m_x, m_qx);
        ++m_result.products;
        m_g = m_qx + m_c;
        m_result.residual = projectedGradientNorm(m_g, m_x, m_lo, m_hi);
        m_result.converged = m_result.residual <= m_options.tolerance;
    }
    m_result.x = std::move(m_x);
}

}  // namespace

QpResult solveBoundedQp(const QpOperator& q, const Eigen::VectorXd& c, const Eigen::VectorXd& lo,
                        const Eigen::VectorXd& hi, const Eigen::VectorXd& x0, const QpSolverOptions& options) {
    return BoundedQpSolver(q, c, lo, hi, x0, options).solve();
}

}  // namespace tc
