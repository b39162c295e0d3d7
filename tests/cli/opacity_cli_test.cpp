// render.transparency "opacity_optimization" through the tubecast binary: a two-frame orbit
// of a small tornado with --dump-system. The dumped system is read back as another tool would
// (Matrix Market Q, one value per line for the vectors) and checked against the solution.
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "io/image_io.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

class OpacityCli : public CliFixture {
protected:
    void writeScene() {
        writeText(dir / "scene.json", R"({
  "dataset": {"generate": "tornado", "lines": 30, "points": 40, "seed": 3},
  "style": {"radius": 0.02, "color": {"attribute": "speed", "colormap": "viridis"}, "opacity": 1.0},
  "camera": {"fit": true, "eye": [1.6, -1.2, 1.25], "target": [0.5, 0.5, 0.5], "up": [0, 0, 1], "fov_deg": 30},
  "image": {"width": 64, "height": 48},
  "animation": {"type": "orbit", "frames": 2, "axis": [0, 0, 1], "degrees": 2},
  "render": {"transparency": "opacity_optimization",
             "opacity": {"segments_per_line": 4, "q": 60, "importance": "length", "tolerance": 1e-7}},
  "output": {"dir": "out", "name": "f.####", "formats": ["exr"], "aovs": []}
}
)");
    }
};

std::vector<double> readVector(const fs::path& p) {
    std::ifstream in(p);
    std::vector<double> v;
    for (double x; in >> x;) v.push_back(x);
    return v;
}

// Matrix Market "coordinate real general" as written by Eigen::saveMarket; fails the test on any
// malformed line.
Eigen::SparseMatrix<double> readMatrixMarket(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);
    std::istringstream header(line);  // Eigen separates the words by two spaces in places
    std::vector<std::string> words;
    for (std::string w; header >> w;) words.push_back(w);
    EXPECT_EQ(words, (std::vector<std::string>{"%%MatrixMarket", "matrix", "coordinate", "real", "general"})) << line;
    while (std::getline(in, line) && !line.empty() && line[0] == '%') {
    }
    std::istringstream size(line);
    long rows = 0, cols = 0, entries = 0;
    size >> rows >> cols >> entries;
    EXPECT_TRUE(size && rows > 0 && rows == cols && entries > 0) << line;
    std::vector<Eigen::Triplet<double>> t;
    for (long k = 0; k < entries; ++k) {
        long i = 0, j = 0;
        double v = 0;
        in >> i >> j >> v;
        EXPECT_TRUE(in && i >= 1 && i <= rows && j >= 1 && j <= cols) << "entry " << k;
        if (!in) break;
        t.emplace_back(int(i - 1), int(j - 1), v);
    }
    double extra = 0;
    EXPECT_FALSE(in >> extra) << "more entries than the size line says";
    Eigen::SparseMatrix<double> q(rows, cols);
    q.setFromTriplets(t.begin(), t.end());
    return q;
}

TEST_F(OpacityCli, TwoFrameOrbitWritesFramesAndAConsistentDumpedSystemAndWarmStarts) {
    writeScene();
    RunResult r = run("render scene.json --dump-system sys");
    ASSERT_EQ(r.code, 0) << r.err;
    const int n = 30 * 4;
    std::vector<nlohmann::json> solve;
    for (const char* frame : {"frame_0000", "frame_0001"}) {
        SCOPED_TRACE(frame);
        const fs::path sys = dir / "sys" / frame;
        const Eigen::SparseMatrix<double> q = readMatrixMarket(sys / "Q.mtx");
        ASSERT_EQ(q.rows(), n);
        const std::vector<double> c = readVector(sys / "c.txt"), a = readVector(sys / "solution.txt"),
                                  shown = readVector(sys / "displayed.txt"), lo = readVector(sys / "lower.txt"),
                                  hi = readVector(sys / "upper.txt"), g = readVector(sys / "g.txt");
        ASSERT_EQ(c.size(), std::size_t(n));
        ASSERT_EQ(a.size(), std::size_t(n));
        ASSERT_EQ(shown.size(), std::size_t(n));
        ASSERT_EQ(g.size(), std::size_t(n));
        // Q is symmetric with diagonal >= 2p (p = 1); c = -2p.
        const Eigen::MatrixXd dense(q);
        EXPECT_LE((dense - dense.transpose()).cwiseAbs().maxCoeff(), 1e-9 * dense.cwiseAbs().maxCoeff());
        EXPECT_GE(dense.diagonal().minCoeff(), 2.0 - 1e-12);
        EXPECT_GT(q.nonZeros(), n);  // the lines occlude one another in this view
        // Opacities (solution and displayed) within their bounds [0, 1]; some faded.
        int faded = 0;
        for (int i = 0; i < n; ++i) {
            EXPECT_EQ(c[i], -2.0);
            EXPECT_EQ(lo[i], 0.0);
            EXPECT_EQ(hi[i], 1.0);
            EXPECT_GE(a[i], 0.0);
            EXPECT_LE(a[i], 1.0);
            EXPECT_GE(shown[i], 0.0);
            EXPECT_LE(shown[i], 1.0);
            EXPECT_GE(g[i], 0.0);
            EXPECT_LE(g[i], 1.0);
            faded += a[i] < 0.9;
        }
        EXPECT_GT(faded, 0);
        // The dumped solution is the minimiser of the dumped system: KKT from the files.
        Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(a.data(), n);
        const Eigen::VectorXd grad = dense * x + Eigen::Map<const Eigen::VectorXd>(c.data(), n);
        double kkt = 0;
        for (int i = 0; i < n; ++i) {
            const double pg = x[i] <= 0 ? std::min(grad[i], 0.0) : x[i] >= 1 ? std::max(grad[i], 0.0) : grad[i];
            kkt = std::max(kkt, std::abs(pg));
        }
        EXPECT_LE(kkt, 1e-5);
        solve.push_back(nlohmann::json::parse(readText(sys / "solve.json")));
        EXPECT_TRUE(solve.back().at("converged").get<bool>());
        EXPECT_EQ(solve.back().at("parts").get<int>(), n);
        // The frame itself: written, premultiplied alpha in [0, 1], lines covering part of it.
        const tc::FrameImages im = tc::readExr((dir / "out" / (std::string("f.") + (frame + 6) + ".exr")).string());
        ASSERT_EQ(im.width, 64);
        std::size_t covered = 0;
        for (std::size_t k = 3; k < im.rgba.size(); k += 4) {
            EXPECT_GE(im.rgba[k], 0.0f);
            EXPECT_LE(im.rgba[k], 1.0f + 1e-6f);
            covered += im.rgba[k] > 0.01f;
        }
        EXPECT_GT(covered, 100u);
        EXPECT_LT(covered, std::size_t(64 * 48));
    }
    // Frame 1 (2 degrees on) starts from frame 0's solution: fewer iterations and products than
    // frame 0's cold start from all ones.
    EXPECT_LT(solve[1].at("iterations").get<int>(), solve[0].at("iterations").get<int>());
    EXPECT_LT(solve[1].at("products").get<int>(), solve[0].at("products").get<int>());
}

}  // namespace
