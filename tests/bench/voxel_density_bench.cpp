// Density voxelization for line AO (core/voxel_density.h) on the tornado at 10^5, 10^6, 10^7
// segments (the first N segments of enough 501-point streamlines; some streamlines stall and come
// out shorter, so N / 500 lines would fall short): voxelizeLines wall time (accumulator allocation
// and zeroing, DDA deposits, conversion to float) and the memory of the volume. Prints a Markdown
// table for docs/performance.md. Run by scripts/bench/voxel_density.sh.
//
//   tubecast_voxel_density_bench [--segments 100000,1000000,10000000] [--points 501]
//                                [--resolution 256]
//                                [--reps 3] [--threads N]
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/error.h"
#include "core/generators.h"
#include "core/scene.h"
#include "core/styling.h"
#include "core/voxel_density.h"

namespace {

using namespace tc::bench;

}  // namespace

int main(int argc, char** argv) try {
    std::vector<std::size_t> segmentCounts{100000, 1000000, 10000000};
    int points = 501, resolution = 256, reps = 3, threads = 0;
    for (int i = 1; i < argc; i += 2) {
        const std::string flag = argv[i];
        if (i + 1 >= argc) {
            std::fprintf(stderr, "error: %s needs a value\n", argv[i]);
            return 2;
        }
        if (flag == "--segments")
            segmentCounts = parseList(argv[i + 1]);
        else if (flag == "--points")
            points = std::atoi(argv[i + 1]);
        else if (flag == "--resolution")
            resolution = std::atoi(argv[i + 1]);
        else if (flag == "--reps")
            reps = std::atoi(argv[i + 1]);
        else if (flag == "--threads")
            threads = std::atoi(argv[i + 1]);
        else {
            std::fprintf(stderr, "error: unknown option %s\n", argv[i]);
            return 2;
        }
    }
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0)
        limit =
            std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    const int usedThreads =
        int(std::min<std::size_t>(tbb::info::default_concurrency(),
                                  tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));

    tc::StyleSpec style;
    style.radius.constant = 0.0025f;
    style.opacity.constant = 0.3f;

    std::printf(
        "Tornado (generateTornado, seed 1), radius 0.0025, opacity 0.3; resolution %d along the "
        "longest axis; %d TBB threads; median of %d runs of voxelizeLines\n\n",
        resolution, usedThreads, reps);
    std::printf(
        "| segments | of lines x points | grid | voxelize (ms) | M segments/s | density (MB) | "
        "+ accumulator (MB) | total density | clamped |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (std::size_t target : segmentCounts) {
        const int lineCount = int(double(target) / double(points - 1) * 1.25) + 1;
        tc::StyledLines lines = tc::styleLines(tc::generateTornado(lineCount, points, 1), style, "bench");
        if (lines.segmentCount() > target) lines.segmentVertices.resize(2 * target);
        std::vector<double> times;
        tc::DensityGrid grid;
        for (int r = 0; r < reps; ++r) {
            grid = tc::makeDensityGrid(lines.bounds, resolution);
            const auto start = Clock::now();
            tc::voxelizeLines(lines, grid);
            times.push_back(msSince(start));
        }
        const double ms = median(times);
        std::printf("| %zu | %d x %d | %dx%dx%d | %.1f | %.1f | %.1f | %.1f | %.4g | %zu |\n", lines.segmentCount(),
                    lineCount, points, grid.size.x, grid.size.y, grid.size.z, ms,
                    double(lines.segmentCount()) / ms / 1000.0, megabytes(grid.bytes()),
                    megabytes(grid.accumulatorBytes()), grid.total(), grid.clampedSegments);
        std::fflush(stdout);
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
}
