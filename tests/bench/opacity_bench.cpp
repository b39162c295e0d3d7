// Opacity optimization per frame (gl/opacity_renderer.h) on generated tornado line fields rendered
// at 1280x1024: fragment-list construction, read-back + sort, h_ij assembly (Algorithm 1), the
// solve, and the resolve; then solves per second on the frame's own system (cold from a = 1, and
// warm from the solution after a 1 % change of the view-dependent term, as in an animation).
// Prints a Markdown table for docs/performance.md.
//
//   tubecast_opacity_bench [--parts 2000,8000,32000,128000] [--points 64] [--size 1280x1024] [--reps 3]
//                          [--drop 0.001,0.01]   (sparsification thresholds to compare with the exact solve)
//                          [--occlusion auto|assembled|fragments|both] [--square-estimate K]
//                          [--scaled-gradient 0|1]   (QpSolverOptions::scaledGradientStep of the timed solves)
//                          [--frames F] [--step-deg D]  (F - 1 more frames of an orbit about z, D degrees apart:
//                                                        the renderer's own warm start from the previous frame)
//                          [--occlusion-scale 1,0.5,0.25]  (render.opacity.occlusion_scale per frame 0;
//                                                 with --frames 1, each compared with the first scale)
//                          [--coarse-scale C]  (render.opacity.coarse_scale of every frame)
//                          [--save-system FILE]  (frame 0's sorted lists, importance and parts of the last size,
//                                                 for tubecast_fragment_occlusion_bench: products without GL;
//                                                 frame N > 0 of --frames to FILE.frameN)
//
// --occlusion both: the frame runs with H assembled, then the same lists give the fragment-list
// operator (core/fragment_occlusion.h), and both are timed on the same system (A/B in one run);
// the row "fragments" then reports its own build time in the h column and the largest opacity
// difference to the assembled solve. "frame opt ms" = lists + read-back/sort + h + the solve.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "core/animation.h"
#include "core/fragment_occlusion.h"
#include "core/generators.h"
#include "core/opacity_optimization.h"
#include "core/scene.h"
#include "core/styling.h"
#include "gl/context.h"
#include "gl/gpu_timer.h"
#include "gl/opacity_renderer.h"
#include "gl/shader_library.h"
#include "opacity_system_file.h"

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
    std::string dropRows, frameRows, occlusion = "auto";
    double squareEstimate = tc::OpacityEnergy::kSquareEstimate;
    int scaledGradient = -1;  // -1: the solver's default
    int frames = 1;
    std::string saveSystem;
    std::vector<float> scales{1.0f};
    float coarseScale = 0;  // render.opacity.coarse_scale
    std::string scaleRows;
    float stepDeg = 2.0f;
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
        else if (!std::strcmp(argv[i], "--occlusion"))
            occlusion = argv[i + 1];
        else if (!std::strcmp(argv[i], "--frames"))
            frames = std::max(1, std::atoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--step-deg"))
            stepDeg = float(std::atof(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--scaled-gradient"))
            scaledGradient = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--square-estimate"))
            squareEstimate = std::atof(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--coarse-scale"))
            coarseScale = float(std::atof(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--occlusion-scale")) {
            scales.clear();
            for (const char* p = argv[i + 1]; *p;) {
                char* end = nullptr;
                scales.push_back(float(std::strtod(p, &end)));
                if (end == p) break;
                p = *end == ',' ? end + 1 : end;
            }
        } else if (!std::strcmp(argv[i], "--save-system"))
            saveSystem = argv[i + 1];
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
            "| parts | occlusion | fragments | pairs | H nnz | lists ms | readback+sort ms | h ms | solve ms (it, "
            "products, residual) | resolve ms | frame opt ms (lists+sort+h+solve) | ms/product (CPU ms) | cold "
            "solves/s "
            "(products, cg) | warm solves/s (it, products) |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (int n : parts) {
            tc::Scene scene;
            scene.dataset.generate = "tornado";
            scene.image.width = width;
            scene.image.height = height;
            scene.render.transparency = tc::Transparency::OpacityOptimization;
            scene.render.opacity.importance = tc::OpacityOptimizationSpec::Importance::Length;
            using Occlusion = tc::OpacityOptimizationSpec::Occlusion;
            scene.render.opacity.occlusion = occlusion == "assembled" || occlusion == "both" ? Occlusion::Assembled
                                             : occlusion == "fragments"                      ? Occlusion::Fragments
                                                                                             : Occlusion::Auto;
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

            // Products, cold and warm solves of one energy.
            struct Rates {
                double productMs = 0, productCpuMs = 0, coldRate = 0, warmRate = 0;
                tc::QpResult cold, warm;
            };
            auto measure = [&](const tc::OpacityEnergy& e, const Eigen::VectorXd& warmStart, const char* label) {
                Rates out;
                const Eigen::Index size = e.size();
                const Eigen::VectorXd lo = Eigen::VectorXd::Zero(size), hi = Eigen::VectorXd::Ones(size);
                Eigen::VectorXd y;
                auto t0 = Clock::now();
                const std::clock_t cpu0 = std::clock();
                for (int r = 0; r < 10; ++r) e.multiply(hi, y);
                out.productMs = msSince(t0) / 10;
                // Process CPU time (all threads): less sensitive to other processes than wall time.
                out.productCpuMs = 100.0 * double(std::clock() - cpu0) / CLOCKS_PER_SEC;
                tc::QpSolverOptions opt;
                opt.tolerance = 1e-4;
                if (scaledGradient >= 0) opt.scaledGradientStep = scaledGradient != 0;
                t0 = Clock::now();
                for (int r = 0; r < reps; ++r) out.cold = tc::solveBoundedQp(e, e.linearTerm(), lo, hi, hi, opt);
                out.coldRate = reps / (msSince(t0) / 1000.0);
                // The next frame of an animation: the linear term moves by 1 %.
                const Eigen::VectorXd c = 1.01 * e.linearTerm();
                t0 = Clock::now();
                for (int r = 0; r < reps; ++r) out.warm = tc::solveBoundedQp(e, c, lo, hi, warmStart, opt);
                out.warmRate = reps / (msSince(t0) / 1000.0);
                // The reported residual is the solver's running gradient; the true one for comparison.
                Eigen::VectorXd gc, gw;
                e.multiply(out.cold.x, gc);
                e.multiply(out.warm.x, gw);
                gc += e.linearTerm();
                gw += c;
                std::fprintf(stderr,
                             "  %s: product %.2f ms wall, %.2f ms CPU; cold: it %d, cg %d, search products %d, "
                             "residual %.2e (true %.2e); warm: it %d, cg %d, search products %d, residual %.2e "
                             "(true %.2e)\n",
                             label, out.productMs, out.productCpuMs, out.cold.iterations, out.cold.cgIterations,
                             out.cold.searchProducts, out.cold.residual,
                             tc::projectedGradientNorm(gc, out.cold.x, lo, hi), out.warm.iterations,
                             out.warm.cgIterations, out.warm.searchProducts, out.warm.residual,
                             tc::projectedGradientNorm(gw, out.warm.x, lo, hi));
                return out;
            };
            // One frame per occlusion scale (render.opacity.occlusion_scale); the first scale is the
            // reference the others' opacities and images are compared with.
            Eigen::VectorXd referenceOpacity;
            std::vector<float> referenceImage;
            for (std::size_t si = 0; si < scales.size(); ++si) {
                const float scale = scales[si];
                scene.render.opacity.occlusionScale = scale;
                scene.render.opacity.coarseScale = coarseScale;
                Rates primary, frag;
                double fragBuildMs = 0, fragMaxDiff = 0;
                std::size_t atOne = 0;
                auto sink = [&](const tc::OpacitySystem& sys) {
                    if (!saveSystem.empty())
                        tc::bench::saveOpacitySystem(
                            sys.frame > 0 ? saveSystem + ".frame" + std::to_string(sys.frame) : saveSystem, *sys.lists,
                            *sys.parts, *sys.importance);
                    if (sys.frame > 0) return;  // later frames: the renderer's own timings only
                    {
                        // Checksums for A/B runs that must give the same numbers.
                        double sd = 0, sa = 0;
                        const Eigen::VectorXd diag = sys.energy->diagonal();
                        for (Eigen::Index i = 0; i < diag.size(); ++i) sd += diag[i] * double(i % 7 + 1);
                        for (Eigen::Index i = 0; i < sys.solution->size(); ++i)
                            sa += (*sys.solution)[i] * double(i % 7 + 1);
                        std::fprintf(stderr, "  frame 0 checksums: diagonal %.17g, solution %.17g\n", sd, sa);
                    }
                    const tc::OpacityEnergy& e = *sys.energy;
                    const Eigen::Index size = e.size();
                    const Eigen::VectorXd lo = Eigen::VectorXd::Zero(size), hi = Eigen::VectorXd::Ones(size);
                    primary = measure(e, *sys.solution, e.fromFragments() ? "fragments" : "assembled");
                    if (occlusion == "both" && sys.h) {
                        for (Eigen::Index i = 0; i < sys.h->nonZeros(); ++i) atOne += sys.h->valuePtr()[i] >= 1.0;
                        const auto t0 = Clock::now();
                        const tc::OpacityEnergy ef(
                            std::make_shared<const tc::FragmentOcclusion>(*sys.lists, size_t(size)), *sys.importance,
                            *sys.parts, e.weights(), squareEstimate);
                        fragBuildMs = msSince(t0);
                        frag = measure(ef, *sys.solution, "fragments");
                        fragMaxDiff = (frag.cold.x - primary.cold.x).lpNorm<Eigen::Infinity>();
                    }
                    const Eigen::VectorXd c = 1.01 * e.linearTerm();
                    if (drops.empty()) return;
                    // Sparsification: the exact and the sparsified minimisers solved tightly, compared.
                    tc::QpSolverOptions tight;
                    tight.tolerance = 1e-9;
                    tight.maxIterations = 2000;
                    if (!sys.h) return;
                    const tc::QpResult exact = tc::solveBoundedQp(e, e.linearTerm(), lo, hi, *sys.solution, tight);
                    auto objective = [&](const Eigen::VectorXd& a) {
                        Eigen::VectorXd qa;
                        e.multiply(a, qa);
                        return 0.5 * a.dot(qa) + e.linearTerm().dot(a);
                    };
                    const double fExact = objective(exact.x);
                    for (double drop : drops) {
                        const tc::OpacityEnergy es(tc::SparseMatrixF(*sys.h), *sys.importance, *sys.parts, e.weights(),
                                                   drop);
                        const tc::QpResult approx = tc::solveBoundedQp(es, es.linearTerm(), lo, hi, exact.x, tight);
                        const tc::SparsificationBound bound =
                            tc::sparsificationBound(e, es, approx.x, 2.0 * e.weights().p);
                        auto t1 = Clock::now();
                        tc::QpResult c0;
                        tc::QpSolverOptions opt4;
                        opt4.tolerance = 1e-4;
                        for (int r = 0; r < reps; ++r) c0 = tc::solveBoundedQp(es, es.linearTerm(), lo, hi, hi, opt4);
                        const double cRate = reps / (msSince(t1) / 1000.0);
                        t1 = Clock::now();
                        tc::QpResult w0;
                        for (int r = 0; r < reps; ++r) w0 = tc::solveBoundedQp(es, c, lo, hi, approx.x, opt4);
                        const double wRate = reps / (msSince(t1) / 1000.0);
                        char line[512];
                        std::snprintf(
                            line, sizeof line,
                            "| %lld | %g | %zu (%.1f %%) | %.1f (%d) | %.1f (%d) | %.4f | %.3f (bound %.3f) | %.2e "
                            "(bound %.2e) |\n",
                            (long long)size, drop, es.nonZeros(),
                            100.0 * double(es.nonZeros()) / double(std::max<std::size_t>(1, e.nonZeros())), cRate,
                            c0.products, wRate, w0.products, (approx.x - exact.x).lpNorm<Eigen::Infinity>(),
                            (approx.x - exact.x).norm(), bound.distance,
                            (objective(approx.x) - fExact) / std::abs(fExact), bound.objective / std::abs(fExact));
                        dropRows += line;
                    }
                };
                auto renderer = tc::gl::OpacityRenderer::create(scene, styled, nullptr, sink);
                tc::FrameImages images;
                tc::gl::StageTimer timer;
                renderer->render(tc::FrameSetup{0, cam, width, height}, images, timer);
                for (const tc::StageTime& st : timer.collect())
                    std::fprintf(stderr, "  %zu parts, stage %s: gpu %.1f ms, cpu %.1f ms\n", std::size_t(n),
                                 st.stage.c_str(), st.gpuMs, st.cpuMs);
                const auto& s = renderer->lastStats();
                if (coarseScale > 0)
                    std::fprintf(stderr,
                                 "  frame 0: coarse solve %d products, then %d products (solve stage %.1f ms)\n",
                                 s.coarse.products, s.solve.products, s.solveMs);
                auto row = [&](const char* mode, double hMs, double solveMs, const Rates& r, const char* extra) {
                    std::printf(
                        "| %zu | %s%s | %llu%s | %llu | %zu | %.0f | %.0f | %.0f | %.1f (%d, %d, %.1e) | %.0f | %.0f | "
                        "%.2f "
                        "(%.2f) | %.1f (%d, %d) | %.1f (%d, %d) |\n",
                        s.parts, mode, extra, (unsigned long long)s.fragments, s.overflow ? " (overflow)" : "",
                        (unsigned long long)s.pairs, s.hNonZeros, s.listsMs, s.readbackMs, hMs, solveMs,
                        s.solve.iterations, s.solve.products, s.solve.residual, s.resolveMs,
                        s.listsMs + s.readbackMs + hMs + solveMs, r.productMs, r.productCpuMs, r.coldRate,
                        r.cold.products, r.cold.cgIterations, r.warmRate, r.warm.iterations, r.warm.products);
                };
                row(s.fromFragments ? "fragments" : "assembled", s.assemblyMs, s.solveMs, primary, "");
                if (occlusion == "both") {
                    char extra[160];
                    std::snprintf(extra, sizeof extra,
                                  " (same lists; solve = its cold solve, it/products of the frame's; max |a - "
                                  "a_assembled| %.1e, %zu entries of H at 1)",
                                  fragMaxDiff, atOne);
                    row("fragments", fragBuildMs, 1000.0 / frag.coldRate, frag, extra);
                }
                if (s.overflow)
                    std::fprintf(stderr, "  %zu parts: %llu of %llu fragments over the pool of %zu nodes\n", s.parts,
                                 (unsigned long long)s.overflow, (unsigned long long)s.fragments, s.capacity);
                std::fflush(stdout);
                // The next frames of an orbit: the renderer warm starts from the previous solution.
                tc::AnimationSpec orbit;
                orbit.type = tc::AnimationSpec::Type::Orbit;
                orbit.axis = {0.0f, 0.0f, 1.0f};
                orbit.frames = 1;
                orbit.degrees = stepDeg;
                for (int f = 1; f < frames; ++f) {
                    tc::gl::StageTimer t;
                    renderer->render(tc::FrameSetup{f, tc::cameraAtFrame(orbit, cam, f), width, height}, images, t);
                    t.collect();
                    const auto& sf = renderer->lastStats();
                    double checksum = 0;  // as frame 0's, for A/B runs of the later frames
                    for (Eigen::Index i = 0; i < sf.solve.x.size(); ++i) checksum += sf.solve.x[i] * double(i % 7 + 1);
                    std::fprintf(stderr,
                                 "  frame %d: solve stage %.1f ms, of which energy set-up %.1f ms; coarse solve: %d "
                                 "products; solve: %d products; solution checksum %.17g; process CPU ms: h_assembly "
                                 "%.1f (wall %.1f), solve %.1f, energy set-up %.1f\n",
                                 f, sf.solveMs, sf.energyMs, sf.coarse.products, sf.solve.products, checksum,
                                 sf.assemblyCpuMs, sf.assemblyMs, sf.solveCpuMs, sf.energyCpuMs);
                    frameRows += "| " + std::to_string(sf.parts) + " | " + std::to_string(f) + " | " +
                                 (sf.fromFragments ? "fragments" : "assembled") + " | " + std::to_string(sf.fragments) +
                                 (sf.overflow ? " (overflow)" : "");
                    char line[400];
                    std::snprintf(line, sizeof line, " | %.0f | %.0f | %.0f | %.1f (%d, %d, %.1e) | %.0f | %.0f |\n",
                                  sf.listsMs, sf.readbackMs, sf.assemblyMs, sf.solveMs, sf.solve.iterations,
                                  sf.solve.products, sf.solve.residual, sf.resolveMs,
                                  sf.listsMs + sf.readbackMs + sf.assemblyMs + sf.solveMs);
                    frameRows += line;
                }
                const auto& st = renderer->lastStats();
                if (si == 0) {
                    referenceOpacity = renderer->displayedOpacities();
                    referenceImage = images.rgba;
                }
                if (scales.size() > 1 && frames == 1) {
                    // Frame 0 of this scale against frame 0 of the reference scale.
                    const Eigen::VectorXd d = (renderer->displayedOpacities() - referenceOpacity).cwiseAbs();
                    std::vector<double> sorted(d.data(), d.data() + d.size());
                    std::sort(sorted.begin(), sorted.end());
                    const double p99 = sorted.empty() ? 0.0 : sorted[std::size_t(0.99 * double(sorted.size() - 1))];
                    double imageMax = 0, imageSum = 0;
                    for (std::size_t k = 0; k < images.rgba.size(); ++k) {
                        const double e = std::abs(double(images.rgba[k]) - double(referenceImage[k]));
                        imageMax = std::max(imageMax, e);
                        imageSum += e;
                    }
                    char line[512];
                    std::snprintf(
                        line, sizeof line,
                        "| %zu | %g | %dx%d | %zu | %.0f | %.1f (%d, %d) | %.2f (%.2f) | %.1f (%d) | %.4f | %.5f | "
                        "%.4f | %.6f | %.4f |\n",
                        st.parts, double(scale), st.occlusionWidth, st.occlusionHeight, st.occlusionFragments,
                        st.assemblyMs, st.solveMs, st.solve.iterations, st.solve.products, primary.productMs,
                        primary.productCpuMs, primary.coldRate, primary.cold.products, d.maxCoeff(), d.mean(), imageMax,
                        imageSum / double(std::max<std::size_t>(1, images.rgba.size())), p99);
                    scaleRows += line;
                }
            }
        }
        if (!frameRows.empty())
            std::printf(
                "\nNext frames of an orbit about z, %.1f degrees apart, warm started from the previous frame:\n\n"
                "| parts | frame | occlusion | fragments | lists ms | readback+sort ms | h ms | solve ms (it, "
                "products, residual) | resolve ms | frame opt ms (lists+sort+h+solve) |\n"
                "|---|---|---|---|---|---|---|---|---|---|\n%s",
                double(stepDeg), frameRows.c_str());
        if (!scaleRows.empty())
            std::printf(
                "\nOcclusion at reduced resolution (render.opacity.occlusion_scale), frame 0, against the first "
                "scale's opacities and image (RGBA, straight floats):\n\n"
                "| parts | scale | H lists px | H fragments | h ms | solve ms (it, products) | ms/product (CPU ms) | "
                "cold solves/s (products) | max abs da | mean abs da | image max diff | image mean diff | 99th pct abs "
                "da |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n%s",
                scaleRows.c_str());
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
