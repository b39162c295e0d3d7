// Opacity optimization per frame (gl/opacity_renderer.h) on generated tornado line fields rendered
// at 1280x1024: fragment-list construction, read-back + sort, h_ij assembly (Algorithm 1), the
// solve, and the resolve; then solves per second on the frame's own system (cold from a = 1, and
// warm from the solution after a 1 % change of the view-dependent term, as in an animation).
// Prints a Markdown table for docs/performance.md.
//
//   tubecast_opacity_bench [--parts 2000,8000,32000,128000] [--points 64] [--size 1280x1024] [--reps 3]
//                          [--drop 0.001,0.01]   (sparsification thresholds to compare with the exact solve)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "core/animation.h"
#include "core/generators.h"
#include "core/opacity_optimization.h"
#include "core/scene.h"
#include "core/styling.h"
#include "gl/context.h"
#include "gl/gpu_timer.h"
#include "gl/opacity_renderer.h"
#include "gl/shader_library.h"

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::vector<int> parseList(const char* text) {
    std::vector<int> v;
    for (const char* p = text; *p;) {
        char* end = nullptr;
        v.push_back(int(std::strtol(p, &end, 10)));
        if (end == p) break;
        p = *end == ',' ? end + 1 : end;
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> parts{2000, 8000, 32000, 128000};
    int points = 64, width = 1280, height = 1024, reps = 3;
    std::vector<double> drops;  // sparsification thresholds to compare against the exact solve
    std::string dropRows;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--parts"))
            parts = parseList(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--points"))
            points = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--reps"))
            reps = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--drop"))
            for (const char* p = argv[i + 1]; *p;) {
                char* end = nullptr;
                drops.push_back(std::strtod(p, &end));
                if (end == p) break;
                p = *end == ',' ? end + 1 : end;
            }
        else if (!std::strcmp(argv[i], "--size"))
            std::sscanf(argv[i + 1], "%dx%d", &width, &height);
    }
    try {
        tc::gl::Context context = tc::gl::Context::create({});
        if (const char* dir = std::getenv("TC_BENCH_SHADER_DIR")) tc::gl::ShaderLibrary::instance().setOverrideDir(dir);
        std::printf(
            "renderer: %s, %dx%d, tornado lines of %d points, 8 parts per line, default weights "
            "(p=1 q=1 r=0.1 s=0.3 lambda=1), importance length, tolerance 1e-4\n\n",
            context.info().renderer.c_str(), width, height, points);
        std::printf(
            "| parts | fragments | H nnz | lists ms | readback+sort ms | h ms | solve ms (it, products, residual) | "
            "resolve ms | ms/product | cold solves/s (products) | warm solves/s (it, products) |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (int n : parts) {
            tc::Scene scene;
            scene.dataset.generate = "tornado";
            scene.image.width = width;
            scene.image.height = height;
            scene.render.transparency = tc::Transparency::OpacityOptimization;
            scene.render.opacity.importance = tc::OpacityOptimizationSpec::Importance::Length;
            scene.style.radius.constant = 0.002f;
            scene.style.opacity.constant = 1.0f;
            scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
            const int lines = std::max(1, n / scene.render.opacity.segmentsPerLine);
            tc::LineSet set = tc::generateTornado(lines, points, 1);
            tc::StyledLines styled = tc::styleLines(set, scene.style, "bench");
            scene.camera.fit = true;
            scene.camera.camera.eye = {0.5f, -1.5f, 1.2f};
            scene.camera.camera.target = {0.5f, 0.5f, 0.5f};
            scene.camera.camera.up = {0.0f, 0.0f, 1.0f};
            const tc::Camera cam = tc::fitCamera(scene.camera, styled.bounds, float(width) / float(height));

            double coldRate = 0, warmRate = 0, productMs = 0;
            tc::QpResult cold, warm;
            auto sink = [&](const tc::gl::OpacitySystem& sys) {
                const tc::OpacityEnergy& e = *sys.energy;
                const Eigen::Index size = e.size();
                const Eigen::VectorXd lo = Eigen::VectorXd::Zero(size), hi = Eigen::VectorXd::Ones(size);
                Eigen::VectorXd y;
                auto t0 = Clock::now();
                const std::clock_t cpu0 = std::clock();
                for (int r = 0; r < 10; ++r) e.multiply(hi, y);
                productMs = msSince(t0) / 10;
                // Process CPU time (all threads): less sensitive to other processes than wall time.
                std::fprintf(stderr, "  product: %.2f ms wall, %.2f ms CPU (all threads)\n", productMs,
                             100.0 * double(std::clock() - cpu0) / CLOCKS_PER_SEC);
                tc::QpSolverOptions opt;
                opt.tolerance = 1e-4;
                t0 = Clock::now();
                for (int r = 0; r < reps; ++r) cold = tc::solveBoundedQp(e, e.linearTerm(), lo, hi, hi, opt);
                coldRate = reps / (msSince(t0) / 1000.0);
                // The next frame of an animation: the linear term moves by 1 %.
                const Eigen::VectorXd c = 1.01 * e.linearTerm();
                t0 = Clock::now();
                for (int r = 0; r < reps; ++r) warm = tc::solveBoundedQp(e, c, lo, hi, *sys.solution, opt);
                warmRate = reps / (msSince(t0) / 1000.0);
                std::fprintf(stderr,
                             "  cold: it %d, cg %d, search products %d; warm: it %d, cg %d, search products %d\n",
                             cold.iterations, cold.cgIterations, cold.searchProducts, warm.iterations,
                             warm.cgIterations, warm.searchProducts);
                if (drops.empty()) return;
                // Sparsification: the exact and the sparsified minimisers solved tightly, compared.
                tc::QpSolverOptions tight;
                tight.tolerance = 1e-9;
                tight.maxIterations = 2000;
                const tc::QpResult exact = tc::solveBoundedQp(e, e.linearTerm(), lo, hi, *sys.solution, tight);
                auto objective = [&](const Eigen::VectorXd& a) {
                    Eigen::VectorXd qa;
                    e.multiply(a, qa);
                    return 0.5 * a.dot(qa) + e.linearTerm().dot(a);
                };
                const double fExact = objective(exact.x);
                for (double drop : drops) {
                    const tc::OpacityEnergy es(*sys.h, *sys.importance, *sys.parts, e.weights(), drop);
                    const tc::QpResult approx = tc::solveBoundedQp(es, es.linearTerm(), lo, hi, exact.x, tight);
                    const tc::SparsificationBound bound = tc::sparsificationBound(e, es, approx.x, 2.0 * e.weights().p);
                    auto t1 = Clock::now();
                    tc::QpResult c0;
                    for (int r = 0; r < reps; ++r) c0 = tc::solveBoundedQp(es, es.linearTerm(), lo, hi, hi, opt);
                    const double cRate = reps / (msSince(t1) / 1000.0);
                    t1 = Clock::now();
                    tc::QpResult w0;
                    for (int r = 0; r < reps; ++r) w0 = tc::solveBoundedQp(es, c, lo, hi, approx.x, opt);
                    const double wRate = reps / (msSince(t1) / 1000.0);
                    char line[512];
                    std::snprintf(
                        line, sizeof line,
                        "| %lld | %g | %zu (%.1f %%) | %.1f (%d) | %.1f (%d) | %.4f | %.3f (bound %.3f) | %.2e "
                        "(bound %.2e) |\n",
                        (long long)size, drop, es.nonZeros(),
                        100.0 * double(es.nonZeros()) / double(std::max<std::size_t>(1, e.nonZeros())), cRate,
                        c0.products, wRate, w0.products, (approx.x - exact.x).lpNorm<Eigen::Infinity>(),
                        (approx.x - exact.x).norm(), bound.distance, (objective(approx.x) - fExact) / std::abs(fExact),
                        bound.objective / std::abs(fExact));
                    dropRows += line;
                }
            };
            auto renderer = tc::gl::OpacityRenderer::create(scene, styled, nullptr, sink);
            tc::FrameImages images;
            tc::gl::StageTimer timer;
            renderer->render(tc::gl::FrameSetup{0, cam, width, height}, images, timer);
            for (const tc::gl::StageTime& st : timer.collect())
                std::fprintf(stderr, "  %zu parts, stage %s: gpu %.1f ms, cpu %.1f ms\n", std::size_t(n),
                             st.stage.c_str(), st.gpuMs, st.cpuMs);
            const auto& s = renderer->lastStats();
            std::printf(
                "| %zu | %llu%s | %zu | %.0f | %.0f | %.0f | %.1f (%d, %d, %.1e) | %.0f | %.2f | %.1f (%d) | %.1f (%d, "
                "%d) |\n",
                s.parts, (unsigned long long)s.fragments, s.overflow ? " (overflow)" : "", s.hNonZeros, s.listsMs,
                s.readbackMs, s.assemblyMs, s.solveMs, s.solve.iterations, s.solve.products, s.solve.residual,
                s.resolveMs, productMs, coldRate, cold.products, warmRate, warm.iterations, warm.products);
            std::fflush(stdout);
        }
        if (!drops.empty())
            std::printf(
                "\nSparsification (h_ij < drop left out), compared with the exact minimiser (both solved to 1e-9):\n\n"
                "| parts | drop | H nnz kept | cold solves/s (products) | warm solves/s (products) | max abs diff | "
                "L2 diff (bound) | rel. objective increase (bound) |\n|---|---|---|---|---|---|---|---|\n%s",
                dropRows.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
