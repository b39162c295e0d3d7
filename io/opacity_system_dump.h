#pragma once
// Dumps one frame's opacity optimization problem (core/opacity_optimization.h) so it can be
// checked with other tools (docs/scene-spec.md, render.opacity.dump_dir): in DIR/frame_NNNN/
//   Q.mtx          the matrix Q of 1/2 a^T Q a + c^T a, Matrix Market coordinate real general
//                  (Eigen::saveMarket, 1-based indices)
//   c.txt          the linear term, one value per line (17 significant digits)
//   g.txt          the importance per part
//   lower.txt, upper.txt   the bounds (0 and 1)
//   solution.txt   the solver's minimiser for this frame
//   displayed.txt  the opacities drawn (the solution blended with the previous frame's)
//   solve.json     iterations, products with Q, projected-gradient residual, parts
// Files are written to temporary names and renamed (io/atomic_file.h).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/opacity_optimization.h"

namespace tc {

struct OpacitySystemDump {
    const SparseMatrixD* q = nullptr;
    const Eigen::VectorXd* c = nullptr;
    const std::vector<double>* g = nullptr;
    const Eigen::VectorXd* lower = nullptr;
    const Eigen::VectorXd* upper = nullptr;
    const Eigen::VectorXd* solution = nullptr;
    const Eigen::VectorXd* displayed = nullptr;
    const QpResult* solve = nullptr;  // may be null
};

// Throws OutputError when the directory or a file cannot be written.
void writeOpacitySystem(const std::string& dir, int frame, const OpacitySystemDump& dump);

}  // namespace tc
