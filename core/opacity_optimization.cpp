#include "core/opacity_optimization.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

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
Eigen::VectorXd projectedGradient(const Eigen::VectorXd& g, const Eigen::VectorXd& x, const Eigen::VectorXd& lo,
                                  const Eigen::VectorXd& hi) {
    Eigen::VectorXd pg = g;
    for (Eigen::Index i = 0; i < g.size(); ++i) {
        if (x[i] <= lo[i])
            pg[i] = std::min(g[i], 0.0);
        else if (x[i] >= hi[i])
            pg[i] = std::max(g[i], 0.0);
    }
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

OpacityEnergy::OpacityEnergy(const SparseMatrixD& h, const std::vector<double>& g, const OpacityParts& parts,
                             const OpacityWeights& weights)
    : m_n(Eigen::Index(parts.partCount())), m_weights(weights) {
    TC_CHECK_OP(h.rows(), ==, m_n);
    TC_CHECK_OP(h.cols(), ==, m_n);
    TC_CHECK_OP(Eigen::Index(g.size()), ==, m_n);
    // (I - G)^lambda with 0^0 = 1: lambda = 0 leaves the unimportant-first weighting out.
    Eigen::VectorXd rowScale(m_n), colScale(m_n);
    for (Eigen::Index i = 0; i < m_n; ++i) {
        rowScale[i] = std::pow(std::max(0.0, 1.0 - g[i]), weights.lambda);
        colScale[i] = g[i];
    }
    // W = (I-G)^lambda H G, V = (I-G)^lambda H^T G.
    m_w = rowScale.asDiagonal() * h * colScale.asDiagonal();
    m_wt = m_w.transpose();
    SparseMatrixD ht = h.transpose();
    m_v = rowScale.asDiagonal() * ht * colScale.asDiagonal();
    m_vt = m_v.transpose();
    m_w.prune(0.0);
    m_wt.prune(0.0);
    m_v.prune(0.0);
    m_vt.prune(0.0);

    // D: one row per pair of adjacent parts of a polyline.
    std::vector<Eigen::Triplet<double>> triplets;
    const int m = parts.partsPerLine;
    Eigen::Index row = 0;
    for (std::size_t l = 0; l < parts.polylineCount(); ++l)
        for (int k = 0; k + 1 < m; ++k, ++row) {
            triplets.emplace_back(row, parts.firstPart[l] + k, -1.0);
            triplets.emplace_back(row, parts.firstPart[l] + k + 1, 1.0);
        }
    m_d.resize(row, m_n);
    m_d.setFromTriplets(triplets.begin(), triplets.end());
    m_dt = m_d.transpose();

    // diag(W W^T)_i = |row i of W|^2, likewise for V; diag(D^T D)_i = |column i of D|^2.
    m_diagonal = Eigen::VectorXd::Constant(m_n, weights.p);
    for (Eigen::Index i = 0; i < m_n; ++i) {
        double d = weights.p;
        for (SparseMatrixD::InnerIterator it(m_w, i); it; ++it) d += weights.q * it.value() * it.value();
        for (SparseMatrixD::InnerIterator it(m_v, i); it; ++it) d += weights.r * it.value() * it.value();
        for (SparseMatrixD::InnerIterator it(m_dt, i); it; ++it) d += weights.s * it.value() * it.value();
        m_diagonal[i] = 2.0 * d;
    }
}

void OpacityEnergy::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    y = m_weights.p * x;
    Eigen::VectorXd t, u;
    if (m_weights.q != 0 && m_w.nonZeros() > 0) {
        multiplyRows(m_wt, x, t);
        multiplyRows(m_w, t, u);
        y += m_weights.q * u;
    }
    if (m_weights.r != 0 && m_v.nonZeros() > 0) {
        multiplyRows(m_vt, x, t);
        multiplyRows(m_v, t, u);
        y += m_weights.r * u;
    }
    if (m_weights.s != 0 && m_d.rows() > 0) {
        multiplyRows(m_d, x, t);
        multiplyRows(m_dt, t, u);
        y += m_weights.s * u;
    }
    y *= 2.0;
}

double OpacityEnergy::energy(const Eigen::VectorXd& a) const {
    Eigen::VectorXd t;
    double e = m_weights.p * (a - Eigen::VectorXd::Ones(m_n)).squaredNorm();
    multiplyRows(m_wt, a, t);
    e += m_weights.q * t.squaredNorm();
    multiplyRows(m_vt, a, t);
    e += m_weights.r * t.squaredNorm();
    multiplyRows(m_d, a, t);
    e += m_weights.s * t.squaredNorm();
    return e;
}

SparseMatrixD OpacityEnergy::assemble() const {
    SparseMatrixD identity(m_n, m_n);
    identity.setIdentity();
    SparseMatrixD wwt = m_w * m_wt, vvt = m_v * m_vt, dtd = m_dt * m_d;
    SparseMatrixD q = 2.0 * (m_weights.p * identity + m_weights.q * wwt + m_weights.r * vvt + m_weights.s * dtd);
    q.prune(0.0);
    return q;
}

double projectedGradientNorm(const Eigen::VectorXd& gradient, const Eigen::VectorXd& x, const Eigen::VectorXd& lo,
                             const Eigen::VectorXd& hi) {
    if (x.size() == 0) return 0;
    return projectedGradient(gradient, x, lo, hi).lpNorm<Eigen::Infinity>();
}

QpResult solveBoundedQp(const QpOperator& q, const Eigen::VectorXd& c, const Eigen::VectorXd& lo,
                        const Eigen::VectorXd& hi, const Eigen::VectorXd& x0, const QpSolverOptions& options) {
    const Eigen::Index n = q.size();
    TC_CHECK_OP(c.size(), ==, n);
    TC_CHECK_OP(lo.size(), ==, n);
    TC_CHECK_OP(hi.size(), ==, n);
    TC_CHECK_OP(x0.size(), ==, n);
    constexpr double kArmijo = 1e-4;
    constexpr int kMaxBacktracks = 40;

    QpResult result;
    Eigen::VectorXd x = clampBox(x0, lo, hi);
    Eigen::VectorXd qx, g, d, qd, y, s, qs;
    q.multiply(x, qx);
    ++result.products;
    g = qx + c;
    const Eigen::VectorXd diagonal = q.diagonal();
    const Eigen::VectorXd inverseDiagonal = diagonal.cwiseMax(1e-300).cwiseInverse();

    // Moves x to P(x + step * dir) with Armijo backtracking on step; qdir = Q dir saves a product
    // whenever no component is clipped. Returns false when no decrease was found.
    auto projectedSearch = [&](const Eigen::VectorXd& dir, const Eigen::VectorXd& qdir, double step) {
        for (int k = 0; k < kMaxBacktracks; ++k, step *= 0.5) {
            y = clampBox(x + step * dir, lo, hi);
            s = y - x;
            const bool clipped = (s - step * dir).lpNorm<Eigen::Infinity>() > 0;
            if (clipped) {
                q.multiply(s, qs);
                ++result.products;
            } else {
                qs = step * qdir;
            }
            const double gs = g.dot(s);
            if (gs >= 0) continue;  // clipping can leave no descent at this step
            if (gs + 0.5 * s.dot(qs) <= kArmijo * gs) {
                x = y;
                qx += qs;
                g = qx + c;
                return true;
            }
        }
        return false;
    };

    Eigen::VectorXd r, z, p, qp, qpFree;
    std::vector<char> isFree(std::size_t(n), 0);
    for (;; ++result.iterations) {
        d = -projectedGradient(g, x, lo, hi);
        result.residual = d.size() ? d.lpNorm<Eigen::Infinity>() : 0.0;
        if (result.residual <= options.tolerance) {
            result.converged = true;
            break;
        }
        if (result.iterations >= options.maxIterations) break;

        // 1. Projected steepest descent, starting from the exact minimiser along d (g.d = -|d|^2).
        q.multiply(d, qd);
        ++result.products;
        const double curvature = d.dot(qd);
        projectedSearch(d, qd, curvature > 0 ? d.squaredNorm() / curvature : 1.0);

        // 2. Truncated PCG on the face of the box the projected step landed on.
        Eigen::Index freeCount = 0;
        for (Eigen::Index i = 0; i < n; ++i) {
            isFree[i] = x[i] > lo[i] && x[i] < hi[i];
            freeCount += isFree[i];
        }
        if (freeCount == 0) continue;
        r = -g;
        for (Eigen::Index i = 0; i < n; ++i)
            if (!isFree[i]) r[i] = 0;
        const double r0 = r.norm();
        if (r0 == 0) continue;
        // Forcing term min(0.1, sqrt|r0|): loose far away, tight near the solution.
        const double stop = std::min(0.1, std::sqrt(r0)) * r0;
        z = inverseDiagonal.cwiseProduct(r);
        p = z;
        double rz = r.dot(z);
        d.setZero(n);
        qd.setZero(n);
        for (int k = 0; k < options.maxCgIterations; ++k) {
            q.multiply(p, qp);
            ++result.products;
            ++result.cgIterations;
            qpFree = qp;
            for (Eigen::Index i = 0; i < n; ++i)
                if (!isFree[i]) qpFree[i] = 0;
            const double pqp = p.dot(qpFree);
            if (!(pqp > 0)) break;
            const double alpha = rz / pqp;
            d += alpha * p;
            qd += alpha * qp;
            r -= alpha * qpFree;
            if (r.norm() <= stop) break;
            z = inverseDiagonal.cwiseProduct(r);
            const double rzNext = r.dot(z);
            p = z + (rzNext / rz) * p;
            rz = rzNext;
        }
        projectedSearch(d, qd, 1.0);
    }
    // The residual above uses the running gradient; recompute it from scratch so the reported
    // value is the true one (rounding accumulates over many updates).
    q.multiply(x, qx);
    ++result.products;
    g = qx + c;
    result.residual = projectedGradientNorm(g, x, lo, hi);
    result.converged = result.residual <= options.tolerance;
    result.x = std::move(x);
    return result;
}

}  // namespace tc
