#pragma once
// Opacity optimization for 3D line fields (Günther, Rössl & Theisel 2013): every polyline is split
// into parts, each part i gets an opacity a_i in [0,1] minimising the bounded least-squares energy
// of the paper's Sect. 4.4 matrix form (docs/scene-spec.md, render.opacity):
//
//   E(a) = p|a - 1|^2 + q|W^T a|^2 + r|V^T a|^2 + s|D a|^2,   0 <= a_i <= 1,
//   W = (I-G)^lambda H G,  V = (I-G)^lambda H^T G,  G = diag(g),
//
// h_ij = how much part i occludes part j (core/occlusion_matrix.h), g the importance per part and
// D the difference of adjacent parts of each polyline. As a QP: 1/2 a^T Q a + c^T a with
// Q = 2(pI + q W W^T + r V V^T + s D^T D), c = -2p 1. No OpenGL, no files.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "core/scene.h"

namespace tc {

using SparseMatrixD = Eigen::SparseMatrix<double, Eigen::RowMajor>;
// H the way OpacityEnergy keeps it: single precision values (h_ij in [0,1] comes from float
// fragment data; products accumulate in double), int columns, compressed rows. occlusionMatrix
// (core/occlusion_matrix.h) builds it directly so the energy takes it over without a copy.
using SparseMatrixF = Eigen::SparseMatrix<float, Eigen::RowMajor, int>;
class FragmentOcclusion;  // core/fragment_occlusion.h

// The parts of a line set. Part k of polyline l (k = 0..m-1, m = segments per line) has global
// index firstPart[l] + k and sits at arc-length fraction t = k / (m - 1) along the polyline. Every
// vertex gets the blending parameter w = firstPart[l] + t * (m - 1): round(w) is the part it
// belongs to, and lerp(a_floor(w), a_floor(w)+1, frac(w)) its opacity. w stays within its own
// polyline's parts (frac(w) = 0 at the last part), as Algorithm 1 needs. w is kept split into the
// polyline's first part and the local w = t * (m - 1): a float global w would lose the fraction's
// precision beyond ~100k parts.
struct OpacityParts {
    int partsPerLine = 8;
    std::vector<std::uint32_t> firstPart;        // per polyline, plus the total at the end
    std::vector<float> vertexLocalW;             // per vertex, t * (m - 1) in [0, m - 1]
    std::vector<std::uint32_t> vertexFirstPart;  // per vertex: firstPart of its polyline

    std::size_t partCount() const { return firstPart.empty() ? 0 : firstPart.back(); }
    std::size_t polylineCount() const { return firstPart.empty() ? 0 : firstPart.size() - 1; }
};

// `offsets` as in LineSet (polyline l has vertices [offsets[l], offsets[l+1])).
OpacityParts partitionLines(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& offsets,
                            int partsPerLine);

// Importance g in [0,1] per part (render.opacity.importance):
// - Constant: 0.5;
// - Length: the polyline's length divided by the longest polyline's (all parts of a line alike);
// - Curvature: the integrated curvature of the part (sum of the turning angles at its vertices)
//   divided by the largest part's;
// - Attribute: the arc-length weighted mean of the linearly interpolated attribute over the part
//   ([t_k - h/2, t_k + h/2], h = 1/(m-1)), mapped from [rangeLo, rangeHi] to [0,1] and clamped.
//   `attribute` holds one value per vertex (NaN values count as rangeLo).
std::vector<double> partImportance(const OpacityParts& parts, const std::vector<glm::vec3>& positions,
                                   const std::vector<std::uint32_t>& offsets, const OpacityOptimizationSpec& spec,
                                   const std::vector<float>* attribute = nullptr);

// A symmetric positive definite operator y = Q x; what the bounded QP solver needs.
class QpOperator {
public:
    virtual ~QpOperator() = default;
    virtual Eigen::Index size() const = 0;
    virtual void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const = 0;
    virtual Eigen::VectorXd diagonal() const = 0;  // for the Jacobi preconditioner
    // A better preconditioner for CG on the free variables, if the operator has one: z = M^-1 r
    // with M symmetric positive definite on the free variables (isFree[i] != 0), z zero elsewhere.
    // Returns false to get Jacobi (diagonal()).
    virtual bool precondition(const Eigen::VectorXd& r, const std::vector<char>& isFree, Eigen::VectorXd& z) const {
        (void)r, (void)isFree, (void)z;
        return false;
    }
};

// Q given explicitly (tests, dumps).
class SparseQpOperator final : public QpOperator {
public:
    explicit SparseQpOperator(const SparseMatrixD& q) : m_q(q) {}
    Eigen::Index size() const override { return m_q.rows(); }
    void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
    Eigen::VectorXd diagonal() const override { return m_q.diagonal(); }

private:
    const SparseMatrixD& m_q;
};

struct OpacityWeights {
    double p = 1, q = 1, r = 0.1, s = 0.3, lambda = 1;
};

// The energy in factored form. With R = (I-G)^lambda and C = G, W W^T = R H C^2 H^T R and
// V V^T = R H^T C^2 H R, so one copy of H serves both terms: a product with Q is two passes over
// H's compressed rows, each computing H u (gather) and H^T v (scatter into per-chunk buffers) at
// once, instead of four sparse products with separate W, W^T, V, V^T, and never forming W W^T
// (far denser than H when many parts overlap). H is stored in single precision (h_ij in [0,1]
// comes from float fragment data; products accumulate in double); D^T D is applied along each
// polyline's parts directly.
class OpacityEnergy final : public QpOperator {
public:
    // The factor k of the fragment-list constructor's diagonal estimate.
    static constexpr double kSquareEstimate = 0.25;

    // `h` is n x n (h_ij: i occludes j), `g` the importance per part. The energy takes `h`'s
    // arrays over (swapped in: `h` is left empty; pass `SparseMatrixF(x)` to keep x), so the
    // renderer's H is never copied. Entries h_ij < dropBelow are pruned in place (sparsification,
    // render.opacity.drop_below, compared on the stored float h_ij; 0 keeps all, and H is then only
    // read for diag(Q)): the solution moves by at most sparsificationBound() from the exact one.
    OpacityEnergy(SparseMatrixF&& h, const std::vector<double>& g, const OpacityParts& parts,
                  const OpacityWeights& weights, double dropBelow = 0);
    // The same from H in double precision (tests, the reference path): zeros are left out, the
    // comparison with dropBelow is on the double h_ij, then each kept h_ij is rounded to float.
    OpacityEnergy(const SparseMatrixD& h, const std::vector<double>& g, const OpacityParts& parts,
                  const OpacityWeights& weights, double dropBelow = 0);
    // H applied from the fragment lists, never assembled (core/fragment_occlusion.h). diag(Q)
    // needs sums of squared entries of H, which the lists do not give in linear time; the
    // preconditioner gets the estimate sum_j h_ij^2 c_j ~= kSquareEstimate * sum_j h_ij c_j (see
    // the constructor). assemble() is not available.
    OpacityEnergy(std::shared_ptr<const FragmentOcclusion> occlusion, const std::vector<double>& g,
                  const OpacityParts& parts, const OpacityWeights& weights, double squareEstimate = kSquareEstimate);

    Eigen::Index size() const override { return m_n; }
    void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
    Eigen::VectorXd diagonal() const override { return m_diagonal; }
    // diag(Q) plus the smoothness term's coupling of adjacent parts (-2s): tridiagonal per
    // polyline, solved exactly (Thomas algorithm) on each run of free parts.
    bool precondition(const Eigen::VectorXd& r, const std::vector<char>& isFree, Eigen::VectorXd& z) const override;

    Eigen::VectorXd linearTerm() const { return Eigen::VectorXd::Constant(m_n, -2.0 * m_weights.p); }
    // E(a) itself (without dropping the constant p*n), for tests.
    double energy(const Eigen::VectorXd& a) const;
    // Q assembled (for --dump-system and tests); can be far denser than H.
    SparseMatrixD assemble() const;
    // Non-zeros of H kept, and left out by dropBelow (0 when H comes from the fragment lists).
    std::size_t nonZeros() const { return std::size_t(m_h.nonZeros()); }
    bool fromFragments() const { return m_fragments != nullptr; }
    // H as the energy keeps it (after dropBelow); empty when it comes from the fragment lists.
    const SparseMatrixF& occlusion() const { return m_h; }
    // Swaps H's arrays out into `into` for reuse (OcclusionAssembler::assemble refills them next
    // frame). Only when done with the energy: H is empty afterwards, the diagonal still the old one.
    void releaseOcclusion(SparseMatrixF& into);
    std::size_t droppedNonZeros() const { return m_dropped; }
    const OpacityWeights& weights() const { return m_weights; }

private:
    // hx = H xg and htx = H^T xs in one pass over H (either output may be null).
    void multiplyBoth(const Eigen::VectorXd& xg, const Eigen::VectorXd& xs, Eigen::VectorXd* hx,
                      Eigen::VectorXd* htx) const;
    // R and C^2 from g; the diagonal from the row and column sums of squares of H C.
    void setScales(const std::vector<double>& g);
    void setDiagonal(const Eigen::VectorXd& rowSum, const Eigen::VectorXd& colSum, const OpacityParts& parts);
    // m_rowChunks and the diagonal from m_h (compressed, final).
    void setUpFromH(const OpacityParts& parts);
    // f(i) for every pair (i, i + 1) of adjacent parts of a polyline: the rows of D.
    template <class F>
    void forEachNeighbourPair(F&& f) const {
        for (std::size_t l = 0; l + 1 < m_firstPart.size(); ++l)
            for (int k = 0; k + 1 < m_partsPerLine; ++k) f(Eigen::Index(m_firstPart[l]) + k);
    }

    Eigen::Index m_n = 0;
    OpacityWeights m_weights;
    SparseMatrixF m_h;
    std::shared_ptr<const FragmentOcclusion> m_fragments;  // instead of m_h
    std::size_t m_dropped = 0;
    Eigen::VectorXd m_rowScale, m_colScale2;  // diagonals of R and C^2
    int m_partsPerLine = 1;
    std::vector<std::uint32_t> m_firstPart;  // polyline boundaries for D^T D
    std::vector<int> m_rowChunks;            // row ranges of about equal non-zeros, for the passes
    Eigen::VectorXd m_diagonal;
};

// What sparsification costs, a posteriori (exact for any convex QP whose Q >= mu I): with a' the
// minimiser of the sparsified problem (Q', same c and box) and delta = |(Q - Q') a'|_2,
//   |a' - a*|_2 <= delta / mu   and   0 <= f(a') - f(a*) <= delta^2 / mu
// for the exact minimiser a* and the exact objective f = 1/2 a^T Q a + c^T a (from the two
// variational inequalities of the KKT conditions). For the opacity energy mu = 2p.
struct SparsificationBound {
    double delta = 0;
    double distance = 0;   // bound on |a' - a*|_2
    double objective = 0;  // bound on f(a') - f(a*)
};
SparsificationBound sparsificationBound(const QpOperator& exact, const QpOperator& sparsified,
                                        const Eigen::VectorXd& solution, double mu);

struct QpSolverOptions {
    double tolerance = 1e-6;  // stop when the projected gradient's max norm is at most this
    int maxIterations = 500;  // outer iterations (one gradient projection + one CG subspace step each)
    int maxCgIterations = 50;
    // The projected gradient step along -diag(Q)^-1 g instead of -g (a diagonal scaling keeps
    // the projection a descent direction). Off: on the opacity problems at 2k and 8k parts it
    // saved no products (`tubecast_opacity_bench --parts 2000,8000 --scaled-gradient 1`, and 0).
    bool scaledGradientStep = false;
    // CG runs on the binding set: the free variables plus those at a bound whose gradient points
    // into the box, and the projected steepest-descent step is taken only when a CG step found no
    // decrease (projected Newton with the binding set, Bertsekas 1982, with GPCG's step as the
    // safeguard). Off: GPCG, a projected gradient step in every iteration whose face is not
    // settled (two products when it is clipped). On 8k / 32k / 128k-part systems saved by
    // `tubecast_opacity_bench --save-system FILE` and solved by `tubecast_fragment_occlusion_bench
    // FILE --next FILE.frame1` (GPCG: with bindingSet false), the binding set took 17 / 26 / 35-36
    // products for a cold solve instead of 24 / 25 / 39, and 9-12 instead of 11 (8k, next frames
    // of an orbit) and 23-27 instead of 23-37 (128k); the cold solves are those of
    // docs/performance.md, "Opacity optimization".
    bool bindingSet = true;
};

struct QpResult {
    Eigen::VectorXd x;
    int iterations = 0;      // outer iterations
    int cgIterations = 0;    // summed over the subspace steps
    int products = 0;        // products with Q: the cost
    int searchProducts = 0;  // of which in the projected line searches (clipped trial steps)
    double residual = 0;     // max norm of the projected gradient at x (KKT residual)
    bool converged = false;
};

// Minimises 1/2 x^T Q x + c^T x subject to lo <= x <= hi (Q SPD) with truncated preconditioned
// conjugate gradients on the free (or binding, QpSolverOptions::bindingSet) variables, each CG
// step followed by a projected line search (Armijo, or cut at the first bound), and projected
// steepest-descent steps to change the active face (GPCG, Moré & Toraldo 1991). Starts from x0
// projected onto the box (warm start).
QpResult solveBoundedQp(const QpOperator& q, const Eigen::VectorXd& c, const Eigen::VectorXd& lo,
                        const Eigen::VectorXd& hi, const Eigen::VectorXd& x0, const QpSolverOptions& options);

// Max norm of the projected gradient of 1/2 x^T Q x + c^T x at x: 0 exactly at the KKT point.
double projectedGradientNorm(const Eigen::VectorXd& gradient, const Eigen::VectorXd& x, const Eigen::VectorXd& lo,
                             const Eigen::VectorXd& hi);

}  // namespace tc
