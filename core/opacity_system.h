#pragma once
// One frame's opacity optimization problem as the renderer solved it (Günther, Rössl & Theisel
// 2013, Sect. 4): what render.opacity.dump_dir writes (io/opacity_system_dump.h) through the
// technique's hook (core/technique_registry.h TechniqueHooks). Pointers are valid during the call.
#include <Eigen/Core>
#include <vector>

#include "core/occlusion_matrix.h"
#include "core/opacity_optimization.h"

namespace tc {

struct OpacitySystem {
    int frame = 0;
    const OpacityEnergy* energy = nullptr;  // Q (factored; assemble() for the matrix) and c
    const SparseMatrixF* h = nullptr;       // the occlusion penalties the energy keeps (after
                                            // drop_below; null when H came from the fragment lists)
    const FragmentLists* lists = nullptr;   // sorted front to back
    const OpacityParts* parts = nullptr;
    const std::vector<double>* importance = nullptr;
    const Eigen::VectorXd* solution = nullptr;
    const Eigen::VectorXd* displayed = nullptr;
    const QpResult* solve = nullptr;
};

}  // namespace tc
