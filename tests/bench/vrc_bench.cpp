// VRC (core/vrc_model.h, gl/vrc_renderer.h) on the tornado. Prints Markdown tables for
// docs/performance.md; run by scripts/bench/vrc.sh.
//   model:   at 10^5 and 10^6 segments, wall time of buildVrcModel (CPU) and buildVrcModelGpu,
//            pieces, bytes per piece and memory against the raw line storage and the per-pixel
//            buffers of the k-buffer at 1920x1080 (the paper's memory table);
//   --frames N (N segments, e.g. 1000000): one frame each at 1920x1080 (the view of
//            configs/tornado_1m.json) of VRC opaque / semi-transparent against the rasterized
//            opaque and k-buffer (k = 8) paths, opacity 0.2 for the transparent ones; then PSNR of
//            semi-transparent VRC (q = 32 and 0) against depth peeling on a 480x270 view of the
//            10^5-segment tornado.
//
//   tubecast_vrc_bench [--segments 100000,1000000] [--points 501] [--resolution 128]
//                      [--quantization 32,0] [--reps 2] [--threads N] [--frames 0|N]
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/animation.h"
#include "core/error.h"
#include "core/generators.h"
#include "core/image_metrics.h"
#include "core/scene.h"
#include "core/styling.h"
#include "core/technique.h"
#include "core/vrc_model.h"
#include "gl/context.h"
#include "gl/gpu_timer.h"
#include "gl/line_geometry.h"
#include "gl/techniques.h"
#include "gl/vrc_renderer.h"

namespace {

using namespace tc::bench;

// The first polylines of a tornado with about `target` segments, styled with `opacity`.
tc::StyledLines tornado(std::size_t target, int points, float opacity) {
    tc::StyleSpec style;
    style.radius.constant = 0.0025f;
    style.opacity.constant = opacity;
    // Some streamlines stall and come out shorter (as in voxel_density_bench.cpp): 25 % more
    // lines, then whole polylines up to the target.
    const int lineCount = int(double(target) / double(points - 1) * 1.25) + 1;
    tc::LineSet set = tc::generateTornado(lineCount, points, 1);
    std::size_t keep = 0, segments = 0;
    while (keep < set.polylineCount() && segments < target) {
        segments += set.offsets[keep + 1] - set.offsets[keep] - 1;
        ++keep;
    }
    set.offsets.resize(keep + 1);
    set.positions.resize(set.offsets.back());
    for (tc::Attribute& a : set.attributes) a.values.resize(set.offsets.back());
    set.updateBounds();
    return tc::styleLines(set, style, "bench");
}

struct Frame {
    tc::FrameImages images;
    double ms = 0;  // sum of the GPU times of the stages (readback included)
    nlohmann::json described;
};

Frame renderOnce(const tc::Scene& scene, const tc::StyledLines& lines, const tc::Camera& cam) {
    std::unique_ptr<tc::Technique> t = tc::gl::createTechnique(scene, lines);
    tc::gl::StageTimer timer;
    Frame f;
    t->render(tc::FrameSetup{0, cam, scene.image.width, scene.image.height}, f.images, timer);
    for (const tc::StageTime& st : timer.collect()) f.ms += st.cpuMs;
    f.described = t->describe();
    return f;
}

void frames(std::size_t segments, int points) {
    tc::CameraSpec cameraSpec;
    cameraSpec.camera.eye = {1.6f, -1.2f, 1.25f};
    cameraSpec.camera.target = {0.5f, 0.5f, 0.5f};
    cameraSpec.camera.up = {0, 0, 1};
    cameraSpec.camera.fovYDeg = 30;
    cameraSpec.fit = true;

    std::printf(
        "\n1920x1080, %d TBB threads, llvmpipe; one frame each, wall time of the technique's stages "
        "(readback included); model build not included (once per dataset)\n\n",
        int(tbb::info::default_concurrency()));
    std::printf("| segments | technique | frame (ms) | notes |\n|---:|---|---:|---|\n");
    for (float opacity : {1.0f, 0.2f}) {
        const tc::StyledLines lines = tornado(segments, points, opacity);
        const tc::Camera cam = tc::fitCamera(cameraSpec, lines.bounds, 1920.0f / 1080.0f);
        for (bool vrc : {false, true}) {
            tc::Scene scene;
            scene.image.width = 1920;
            scene.image.height = 1080;
            scene.render.transparency = opacity < 1 ? tc::Transparency::KBuffer : tc::Transparency::Opaque;
            if (vrc) scene.render.technique = tc::RenderTechnique::VoxelRaycast;
            scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
            const Frame f = renderOnce(scene, lines, cam);
            std::string notes;
            if (vrc)
                notes = "q 32, res 128, " + std::to_string(f.described.value("pieces", 0)) + " pieces (" +
                        std::to_string(f.described.value("copies", 0)) + " copies), build " +
                        std::to_string(int(f.described.value("build_ms", 0.0))) + " ms";
            std::printf("| %zu | %s %s | %.0f | %s |\n", lines.segmentCount(), vrc ? "VRC" : "rasterized",
                        opacity < 1 ? "transparent (0.2)" : "opaque", f.ms, notes.c_str());
            std::fflush(stdout);
        }
    }

    std::printf("\nQuality: semi-transparent (opacity 0.2) VRC vs depth peeling, 480x270, 10^5 segments\n\n");
    std::printf("| q | neighbors | PSNR (dB) | max error |\n|---:|---|---:|---:|\n");
    const tc::StyledLines small = tornado(100000, points, 0.2f);
    const tc::Camera cam = tc::fitCamera(cameraSpec, small.bounds, 480.0f / 270.0f);
    tc::Scene peel;
    peel.image.width = 480;
    peel.image.height = 270;
    peel.render.transparency = tc::Transparency::DepthPeeling;
    peel.output.aovDepth = peel.output.aovNormal = peel.output.aovId = false;
    const Frame reference = renderOnce(peel, small, cam);
    for (int q : {32, 0})
        for (bool neighbors : {false, true}) {
            tc::Scene scene = peel;
            scene.render.technique = tc::RenderTechnique::VoxelRaycast;
            scene.render.transparency = tc::Transparency::KBuffer;
            scene.render.vrc.quantization = q;
            scene.render.vrc.neighbors = neighbors;
            const Frame f = renderOnce(scene, small, cam);
            const tc::ImageMetrics m = tc::compareRgba(f.images.rgba, reference.images.rgba);
            std::printf("| %d | %s | %.1f | %.3f |\n", q, neighbors ? "on" : "off", m.psnr, m.maxError);
            std::fflush(stdout);
        }
}

}  // namespace

int main(int argc, char** argv) try {
    std::vector<std::size_t> segmentCounts{100000, 1000000};
    std::vector<std::size_t> quantizations{32, 0};
    int points = 501, resolution = 128, reps = 2, threads = 0;
    std::size_t frameSegments = 0;
    for (int i = 1; i < argc; i += 2) {
        const std::string flag = argv[i];
        if (i + 1 >= argc) {
            std::fprintf(stderr, "error: %s needs a value\n", argv[i]);
            return 2;
        }
        if (flag == "--segments")
            segmentCounts = parseList(argv[i + 1]);
        else if (flag == "--quantization")
            quantizations = parseList(argv[i + 1]);
        else if (flag == "--points")
            points = std::atoi(argv[i + 1]);
        else if (flag == "--resolution")
            resolution = std::atoi(argv[i + 1]);
        else if (flag == "--reps")
            reps = std::atoi(argv[i + 1]);
        else if (flag == "--threads")
            threads = std::atoi(argv[i + 1]);
        else if (flag == "--frames")
            frameSegments = parseList(argv[i + 1]).at(0);
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

    const std::size_t pixels = 1920 * 1080;
    const tc::gl::Context context = tc::gl::Context::create(tc::gl::ContextConfig{});

    std::printf(
        "Tornado (generateTornado, seed 1, %d points per line), radius 0.0025, opacity 0.3; VRC resolution %d "
        "along the longest axis; %d TBB threads; median of %d runs of buildVrcModel (incl. the Eq. 1 LoD "
        "pyramid); GPU: buildVrcModelGpu on llvmpipe (upload to finished model, no readback)\n\n",
        points, resolution, usedThreads, reps);
    std::printf(
        "| segments | q | grid | CPU build (ms) | GPU build (ms) | pieces | pieces / segment | B / piece | model (MB) "
        "| LoD (MB) | "
        "raw lines (MB) | k-buffer k=8 @1080p (MB) |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (std::size_t target : segmentCounts) {
        const tc::StyledLines lines = tornado(target, points, 0.3f);
        const std::size_t rawBytes = tc::gl::LineGeometry::uploadBytes(lines);
        for (std::size_t q : quantizations) {
            tc::VrcBuildOptions options;
            options.resolution = resolution;
            options.quantization = int(q);
            std::vector<double> times;
            tc::VrcModel model;
            for (int r = 0; r < reps; ++r) {
                model = tc::VrcModel();
                const auto start = Clock::now();
                model = tc::buildVrcModel(lines, options);
                times.push_back(msSince(start));
            }
            double gpuMs = 0;
            const tc::VrcModel gpu = tc::gl::buildVrcModelGpu(lines, options, &gpuMs);
            if (gpu.pieceCount() != model.pieceCount() || gpu.voxels.size() != model.voxels.size())
                std::fprintf(stderr, "warning: GPU model differs from the CPU model\n");
            std::printf("| %zu | %zu | %dx%dx%d | %.0f | %.0f | %zu | %.2f | %zu | %.1f | %.1f | %.1f | %.1f |\n",
                        lines.segmentCount(), q, model.size.x, model.size.y, model.size.z, median(times), gpuMs,
                        model.pieceCount(), double(model.pieceCount()) / double(lines.segmentCount()),
                        model.bytesPerPiece(), megabytes(model.bytes()), megabytes(model.lodBytes()),
                        megabytes(rawBytes), megabytes(pixels * 8 * 8 + pixels * 16));
            std::fflush(stdout);
        }
    }
    if (frameSegments > 0) frames(frameSegments, points);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
}
