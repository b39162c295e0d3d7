#include "io/opacity_system_dump.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unsupported/Eigen/SparseExtra>

#include "core/error.h"
#include "io/atomic_file.h"

namespace tc {

namespace {

template <class Write>
void writeAtomically(const std::string& path, Write&& write) {
    AtomicFile file(path);
    {
        std::ofstream out(file.tempPath());
        if (!out) throw OutputError(path + ": cannot write");
        write(out);
        if (!out) throw OutputError(path + ": cannot write");
    }
    file.commit();
}

template <class Vector>
void writeVector(const std::string& path, const Vector& v) {
    writeAtomically(path, [&](std::ofstream& out) {
        char buffer[32];
        for (auto i = decltype(v.size())(0); i < v.size(); ++i) {
            std::snprintf(buffer, sizeof buffer, "%.17g\n", double(v[i]));
            out << buffer;
        }
    });
}

}  // namespace

void writeOpacitySystem(const std::string& dir, int frame, const OpacitySystemDump& d) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d", frame);
    const std::string base = (std::filesystem::path(dir) / name).string();
    ensureWritableDir(base);
    const auto path = [&](const char* file) { return (std::filesystem::path(base) / file).string(); };
    {
        AtomicFile q(path("Q.mtx"));
        // saveMarket picks nothing from the name; it writes the coordinate format with 17 digits.
        if (!Eigen::saveMarket(*d.q, q.tempPath())) throw OutputError(q.finalPath() + ": cannot write");
        q.commit();
    }
    writeVector(path("c.txt"), *d.c);
    writeVector(path("g.txt"), *d.g);
    writeVector(path("lower.txt"), *d.lower);
    writeVector(path("upper.txt"), *d.upper);
    writeVector(path("solution.txt"), *d.solution);
    writeVector(path("displayed.txt"), *d.displayed);
    nlohmann::json info = {{"frame", frame}, {"parts", d.c->size()}};
    if (d.solve)
        info.update({{"iterations", d.solve->iterations},
                     {"cg_iterations", d.solve->cgIterations},
                     {"products", d.solve->products},
                     {"residual", d.solve->residual},
                     {"converged", d.solve->converged}});
    writeAtomically(path("solve.json"), [&](std::ofstream& out) { out << info.dump(2) << "\n"; });
}

}  // namespace tc
