// Products with H from the fragment lists (core/fragment_occlusion.h) and with Q, and cold solves,
// on a system saved by `tubecast_opacity_bench --save-system FILE`: the CPU part of opacity
// optimization without the GL frame, for A/B runs of the product (docs/performance.md, "Opacity
// optimization").
//
//   tubecast_fragment_occlusion_bench FILE [--reps 10] [--solves 1] [--block-slots 4096 (0: automatic)] [--assembled 1]
//                                     [--reuse 1]   (with --assembled 1: buffers and H kept from call to call)
//                                     [--scale S]   (the lists subsampled as render.opacity.occlusion_scale S)
//                                     [--coarse C]  (also: a solve warm started from the solution of the lists
//                                                    subsampled at C, both timed together)
//                                     [--next FILE2] (also: FILE2's system, e.g. the next frame saved as FILE.frame1,
//                                                    solved warm from the last cold solution, as the renderer does)
//
// --assembled 1: H assembled from the lists (core/occlusion_matrix.h) instead, `reps` times (wall,
// CPU and minor page faults per call; with --reuse 1 by one OcclusionAssembler into the previous
// H, as the renderer's frames); prints the energy's set-up from H (what the renderer's solve stage
// pays per frame), Q products and cold solves.
//
// Prints the set-up time, H products (both outputs), Q products and cold solves (tolerance 1e-4,
// from a = 1), each as wall and process CPU time (all threads).
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>

#include "bench_util.h"
#include "core/fragment_occlusion.h"
#include "core/occlusion_matrix.h"
#include "core/opacity_optimization.h"
#include "opacity_system_file.h"

namespace {

long minorFaults() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_minflt;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE [--reps R] [--solves S]\n", argv[0]);
        return 2;
    }
    int reps = 10, solves = 1;
    bool assembled = false, reuse = false;
    double scale = 1;            // render.opacity.occlusion_scale: the lists subsampled first
    double coarse = 0;           // > 0: also a solve started from the solution at this subsampling scale
    const char* next = nullptr;  // the next frame's system, solved from the cold solution
    std::size_t blockSlots = 0;  // the constructor's choice
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--reps")) reps = std::atoi(argv[i + 1]);
        if (!std::strcmp(argv[i], "--solves")) solves = std::atoi(argv[i + 1]);
        if (!std::strcmp(argv[i], "--block-slots")) blockSlots = std::size_t(std::atoi(argv[i + 1]));
        if (!std::strcmp(argv[i], "--assembled")) assembled = std::atoi(argv[i + 1]) != 0;
        if (!std::strcmp(argv[i], "--reuse")) reuse = std::atoi(argv[i + 1]) != 0;
        if (!std::strcmp(argv[i], "--scale")) scale = std::atof(argv[i + 1]);
        if (!std::strcmp(argv[i], "--coarse")) coarse = std::atof(argv[i + 1]);
        if (!std::strcmp(argv[i], "--next")) next = argv[i + 1];
    }
    using tc::bench::Clock;
    using tc::bench::msSince;
    auto cpuMs = [](std::clock_t c0) { return 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC; };
    try {
        // A saved system, its lists subsampled as render.opacity.occlusion_scale `scale`.
        auto loadSystem = [&](const char* path) {
            tc::bench::OpacitySystemFile loaded = tc::bench::loadOpacitySystem(path);
            if (scale < 1) {
                const int height = int(loaded.lists.pixelCount() / std::size_t(loaded.lists.width));
                loaded.lists = tc::subsampleLists(loaded.lists, height, scale);
                std::printf("%s: lists subsampled at scale %g: %dx%d px, %zu fragments\n", path, scale,
                            loaded.lists.width, int(loaded.lists.pixelCount() / std::size_t(loaded.lists.width)),
                            loaded.lists.fragments.size());
            }
            return loaded;
        };
        tc::bench::OpacitySystemFile sys = loadSystem(argv[1]);
        const std::size_t n = sys.parts.partCount();
        auto printSolve = [&](const char* label, const tc::QpResult& r, Clock::time_point t0, std::clock_t c0) {
            std::printf(
                "%s: %.1f ms wall, %.1f ms CPU; it %d, cg %d, products %d (search %d), residual %.2e, sum a %.17g\n",
                label, msSince(t0), cpuMs(c0), r.iterations, r.cgIterations, r.products, r.searchProducts, r.residual,
                r.x.sum());
        };
        tc::QpSolverOptions opt;
        opt.tolerance = 1e-4;
        const Eigen::VectorXd lo = Eigen::VectorXd::Zero(Eigen::Index(n)),
                              ones = Eigen::VectorXd::Ones(Eigen::Index(n));
        // --next: the next frame's system (H built the same way as this one's), solved from `from`.
        auto solveNext = [&](const Eigen::VectorXd& from) {
            if (!next) return;
            const tc::bench::OpacitySystemFile sys2 = loadSystem(next);
            const tc::OpacityEnergy energy2 =
                assembled ? tc::OpacityEnergy(tc::occlusionMatrix(sys2.lists, n), sys2.importance, sys2.parts,
                                              tc::OpacityWeights{})
                          : tc::OpacityEnergy(std::make_shared<const tc::FragmentOcclusion>(sys2.lists, n, blockSlots),
                                              sys2.importance, sys2.parts, tc::OpacityWeights{});
            for (int s = 0; s < std::max(1, solves); ++s) {
                const auto t0 = Clock::now();
                const std::clock_t c0 = std::clock();
                const tc::QpResult r = tc::solveBoundedQp(energy2, energy2.linearTerm(), lo, ones, from, opt);
                printSolve("next frame, warm", r, t0, c0);
                std::printf("  max |change| from the previous solution %.4f\n", (r.x - from).lpNorm<Eigen::Infinity>());
            }
        };
        auto t0 = Clock::now();
        std::clock_t c0 = std::clock();
        if (assembled) {
            // H assembled `reps` times, each after the previous one was freed (as in the renderer's
            // frames): wall, process CPU and minor page faults per call.
            // --reuse 1: one OcclusionAssembler refills its buffers and the previous H, as the renderer does.
            tc::SparseMatrixF h;
            tc::OcclusionAssembler assembler;
            double leastH = 1e300, wallH = 0, cpuH = 0;
            long faultsH = 0;
            for (int r = 0; r < std::max(1, reps); ++r) {
                if (!reuse) {
                    tc::SparseMatrixF previous;
                    h.swap(previous);
                }
                const long f1 = minorFaults();
                const auto t1 = Clock::now();
                const std::clock_t c1 = std::clock();
                if (reuse) {
                    assembler.assemble(sys.lists, n, h);
                } else {
                    tc::SparseMatrixF built = tc::occlusionMatrix(sys.lists, n);
                    h.swap(built);
                }
                cpuH += cpuMs(c1);
                const double wall = msSince(t1);
                faultsH += minorFaults() - f1;
                wallH += wall;
                leastH = std::min(leastH, wall);
            }
            const int hReps = std::max(1, reps);
            std::printf(
                "%zu parts, H assembled: %lld non-zeros, %.1f ms wall, %.1f ms CPU, %ld minor faults per call "
                "(least wall %.1f)\n",
                n, (long long)h.nonZeros(), wallH / hReps, cpuH / hReps, faultsH / hReps, leastH);
            std::unique_ptr<tc::OpacityEnergy> energy;
            double least = 1e300, wallSum = 0, cpuSum = 0;
            for (int r = 0; r < reps; ++r) {
                energy.reset();
                tc::SparseMatrixF copy = h;  // the energy takes H over; the copy is not timed
                const auto t1 = Clock::now();
                const std::clock_t c1 = std::clock();
                energy = std::make_unique<tc::OpacityEnergy>(std::move(copy), sys.importance, sys.parts,
                                                             tc::OpacityWeights{});
                cpuSum += cpuMs(c1);
                wallSum += msSince(t1);
                least = std::min(least, msSince(t1));
            }
            double dsum = 0;
            for (Eigen::Index i = 0; i < energy->diagonal().size(); ++i)
                dsum += energy->diagonal()[i] * double(i % 7 + 1);
            std::printf(
                "energy set-up from H: %.2f ms wall, %.2f ms CPU per call (least wall %.2f); diagonal checksum %.17g\n",
                wallSum / reps, cpuSum / reps, least, dsum);
            const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(Eigen::Index(n), 0.1, 1.0);
            Eigen::VectorXd y;
            energy->multiply(x, y);  // warm-up
            least = 1e300;
            t0 = Clock::now();
            c0 = std::clock();
            for (int r = 0; r < reps; ++r) {
                const auto t1 = Clock::now();
                energy->multiply(x, y);
                least = std::min(least, msSince(t1));
            }
            std::printf("Q x: %.2f ms wall, %.2f ms CPU per product (least wall %.2f); checksum %.17g\n",
                        msSince(t0) / reps, cpuMs(c0) / reps, least, y.sum());
            Eigen::VectorXd solution = ones;
            for (int s = 0; s < solves; ++s) {
                t0 = Clock::now();
                c0 = std::clock();
                const tc::QpResult r = tc::solveBoundedQp(*energy, energy->linearTerm(), lo, ones, ones, opt);
                printSolve("cold solve", r, t0, c0);
                solution = r.x;
            }
            solveNext(solution);
            return 0;
        }
        auto occlusion = std::make_shared<const tc::FragmentOcclusion>(sys.lists, n, blockSlots);
        std::printf("%zu parts, %zu fragments in lists of >= 2, %llu pairs\n", n, occlusion->fragmentCount(),
                    (unsigned long long)occlusion->pairCount());
        std::printf("set-up: %.1f ms wall, %.1f ms CPU\n", msSince(t0), cpuMs(c0));
        const tc::OpacityEnergy energy(occlusion, sys.importance, sys.parts, tc::OpacityWeights{});
        Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(Eigen::Index(n), 0.1, 1.0), hx, hty, y;
        occlusion->multiply(&x, &hx, &x, &hty);  // warm-up
        // Per call: the mean, and the least CPU time of one call (the machine is shared).
        t0 = Clock::now();
        c0 = std::clock();
        double least = 1e300;
        for (int r = 0; r < reps; ++r) {
            const std::clock_t c1 = std::clock();
            occlusion->multiply(&x, &hx, &x, &hty);
            least = std::min(least, cpuMs(c1));
        }
        std::printf("H x and H^T y: %.2f ms wall, %.2f ms CPU per call (least %.2f); checksums %.9e %.9e\n",
                    msSince(t0) / reps, cpuMs(c0) / reps, least, hx.sum(), hty.sum());
        t0 = Clock::now();
        c0 = std::clock();
        least = 1e300;
        for (int r = 0; r < reps; ++r) {
            const std::clock_t c1 = std::clock();
            energy.multiply(x, y);
            least = std::min(least, cpuMs(c1));
        }
        std::printf("Q x: %.2f ms wall, %.2f ms CPU per product (least %.2f); checksum %.9e\n", msSince(t0) / reps,
                    cpuMs(c0) / reps, least, y.sum());
        Eigen::VectorXd solution = ones;
        for (int s = 0; s < solves; ++s) {
            t0 = Clock::now();
            c0 = std::clock();
            const tc::QpResult r = tc::solveBoundedQp(energy, energy.linearTerm(), lo, ones, ones, opt);
            printSolve("cold solve", r, t0, c0);
            solution = r.x;
        }
        solveNext(solution);
        if (coarse > 0) {
            // A cold solve in two steps: the system of the lists subsampled at `coarse` solved
            // from a = 1, then this one warm started from its solution (same tolerance).
            t0 = Clock::now();
            c0 = std::clock();
            const int height = int(sys.lists.pixelCount() / std::size_t(sys.lists.width));
            const tc::FragmentLists small = tc::subsampleLists(sys.lists, height, coarse);
            const tc::OpacityEnergy ec(std::make_shared<const tc::FragmentOcclusion>(small, n), sys.importance,
                                       sys.parts, tc::OpacityWeights{});
            const double setupMs = msSince(t0);
            const tc::QpResult rc = tc::solveBoundedQp(ec, ec.linearTerm(), lo, ones, ones, opt);
            const double coarseMs = msSince(t0);
            const tc::QpResult r = tc::solveBoundedQp(energy, energy.linearTerm(), lo, ones, rc.x, opt);
            std::printf(
                "two-level solve (coarse %g): %.1f ms wall, %.1f ms CPU (coarse set-up %.1f ms, coarse solve until "
                "%.1f ms: products %d); fine: it %d, cg %d, products %d (search %d), residual %.2e, sum a %.6f\n",
                coarse, msSince(t0), cpuMs(c0), setupMs, coarseMs, rc.products, r.iterations, r.cgIterations,
                r.products, r.searchProducts, r.residual, r.x.sum());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
