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
//   --sets configs/bench/brain_2m.json,...: per scene file (its dataset, style, camera; VRC at
//            its defaults), the model build on the CPU (buildVrcModel) and the GPU
//            (buildVrcModelGpu), interleaved CPU GPU GPU CPU, wall time of the whole call each,
//            and whether the two models are identical;
//   --lod 1 (with --sets, instead of the build table): the LoD tables (render.vrc.lod) on each set: one frame per
//   variant at
//            1920x1080 (variants in order, then in reverse; both times shown), transparent at
//            opacity 0.3 and opaque, the LoD volume's memory, the share of samples per level, PSNR
//            at 1080p against the same mode without LoD and, with --psnr-size WxH, against depth
//            peeling of the same view at that size (minutes per frame on the dense sets); plus
//            rows rendering the LoD volume alone from level L up (the shape of the paper's
//            per-level results).
//
//   tubecast_vrc_bench [--segments 100000,1000000] [--points 501] [--resolution 128]
//                      [--quantization 32,0] [--reps 2] [--threads N] [--frames 0|N]
//                      [--sets a.json,b.json] [--lod 0|1] [--psnr-size WxH]
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
#include "io/dataset.h"

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

std::string loadAverage() {
    std::FILE* f = std::fopen("/proc/loadavg", "r");
    double a = 0, b = 0, c = 0;
    if (!f) return "?";
    const int n = std::fscanf(f, "%lf %lf %lf", &a, &b, &c);
    std::fclose(f);
    if (n != 3) return "?";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.1f %.1f %.1f", a, b, c);
    return buf;
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

std::vector<std::string> splitCommas(const std::string& text) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find(',', start), text.size());
        if (end > start) parts.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return parts;
}

bool sameModel(const tc::VrcModel& a, const tc::VrcModel& b) {
    if (a.voxels.size() != b.voxels.size() || a.compact.size() != b.compact.size() || a.exact.size() != b.exact.size())
        return false;
    auto same = [](const auto& x, const auto& y) {
        return x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
    };
    return same(a.voxels, b.voxels) && same(a.compact, b.compact) && same(a.exact, b.exact);
}

struct BenchSet {
    std::string name;
    tc::Scene scene;
    tc::StyledLines lines;
};

BenchSet loadSet(const std::string& path) {
    BenchSet set;
    set.name = path.substr(path.find_last_of('/') + 1);
    set.name = set.name.substr(0, set.name.rfind(".json"));
    set.scene = tc::loadScene(path);
    const tc::DatasetLoad data = tc::loadDataset(set.scene.dataset);
    set.lines = tc::styleLines(data.lines, set.scene.style, set.scene.file);
    return set;
}

// CPU and GPU model builds, interleaved, as the renderer builds them (copies on).
void buildTable(const std::vector<BenchSet>& sets) {
    std::printf(
        "\nModel build, wall time of the whole call (GPU: upload, build, read-back and the copies on the CPU), "
        "CPU GPU GPU CPU; %d TBB threads, llvmpipe\n\n",
        int(tbb::info::default_concurrency()));
    std::printf("| data set | segments | pieces | CPU build (ms) | GPU build (ms) | GPU / CPU | same model | load |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---|---|\n");
    for (const BenchSet& set : sets) {
        tc::VrcBuildOptions options;
        options.resolution = set.scene.render.vrc.resolution;
        options.quantization = set.scene.render.vrc.quantization;
        options.lod = false;
        options.dilate = true;
        std::vector<double> cpu, gpu;
        tc::VrcModel cpuModel, gpuModel;
        for (int k = 0; k < 4; ++k) {
            const bool onGpu = k == 1 || k == 2;
            const auto start = Clock::now();
            tc::VrcModel m =
                onGpu ? tc::gl::buildVrcModelGpu(set.lines, options) : tc::buildVrcModel(set.lines, options);
            (onGpu ? gpu : cpu).push_back(msSince(start));
            (onGpu ? gpuModel : cpuModel) = std::move(m);
        }
        const double c = 0.5 * (cpu[0] + cpu[1]), g = 0.5 * (gpu[0] + gpu[1]);
        std::printf("| %s | %zu | %zu | %.0f, %.0f | %.0f, %.0f | %.2fx | %s | %s |\n", set.name.c_str(),
                    set.lines.segmentCount(), cpuModel.pieceCount(), cpu[0], cpu[1], gpu[0], gpu[1], g / c,
                    sameModel(cpuModel, gpuModel) ? "yes" : "NO", loadAverage().c_str());
        std::fflush(stdout);
    }
}

struct LodVariant {
    const char* name;
    bool transparent, lod;
    float footprint, opacityStart;
    int minLevel = 0;
};

void lodTable(const BenchSet& set, int psnrWidth, int psnrHeight) {
    tc::VrcBuildOptions options;
    options.resolution = set.scene.render.vrc.resolution;
    options.quantization = set.scene.render.vrc.quantization;
    options.lod = false;
    options.dilate = true;
    const tc::VrcModel model = tc::buildVrcModel(set.lines, options);
    tc::StyledLines transparentLines = set.lines;
    for (glm::vec4& c : transparentLines.color) c.w = 0.3f;
    const tc::VrcModel transparentModel = tc::buildVrcModel(transparentLines, options);

    std::vector<LodVariant> variants = {
        {"transparent, LoD off", true, false, 1, 0.5f},
        {"transparent, LoD on (defaults: footprint 1, opacity_start 0.5)", true, true, 1, 0.5f},
        {"transparent, opacity_start 0.25", true, true, 1, 0.25f},
        {"transparent, opacity_start 0.75", true, true, 1, 0.75f},
        {"transparent, footprint 8, opacity_start 1 (off)", true, true, 8, 1.0f},
        {"opaque, LoD off", false, false, 1, 0.5f},
        {"opaque, footprint 1", false, true, 1, 0.5f},
        {"opaque, footprint 8", false, true, 8, 0.5f},
    };
    for (int level = 0; level < 4; ++level) {
        static const char* names[] = {"transparent, volume only, levels >= 0", "transparent, volume only, levels >= 1",
                                      "transparent, volume only, levels >= 2", "transparent, volume only, levels >= 3"};
        variants.push_back({names[level], true, true, 0, 0.0f, level});
    }
    auto sceneFor = [&](const LodVariant& v, int w, int h) {
        tc::Scene scene = set.scene;
        scene.image.width = w;
        scene.image.height = h;
        scene.render.technique = tc::RenderTechnique::VoxelRaycast;
        scene.render.transparency = v.transparent ? tc::Transparency::KBuffer : tc::Transparency::Opaque;
        scene.render.vrc.lod.enabled = v.lod;
        scene.render.vrc.lod.pixelFootprint = v.footprint;
        scene.render.vrc.lod.opacityStart = v.opacityStart;
        scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
        return scene;
    };
    auto renderer = [&](const LodVariant& v, int w, int h) {
        const tc::Scene scene = sceneFor(v, w, h);
        std::unique_ptr<tc::gl::VrcRenderer> r = tc::gl::VrcRenderer::create(
            scene, v.transparent ? transparentLines : set.lines, v.transparent ? transparentModel : model);
        r->setLodMinLevel(v.minLevel);
        return r;
    };
    auto frame = [&](tc::gl::VrcRenderer& r, const tc::Camera& cam, int w, int h) {
        tc::gl::StageTimer timer;
        Frame f;
        r.render(tc::FrameSetup{0, cam, w, h}, f.images, timer);
        for (const tc::StageTime& st : timer.collect()) f.ms += st.cpuMs;
        f.described = r.describe();
        return f;
    };

    // Frame times at 1080p: every variant once in order, then once in reverse. PSNR against the
    // variant without LoD of the same mode (in order, it comes first), at 1080p.
    const tc::Camera cam = tc::fitCamera(set.scene.camera, set.lines.bounds, 1920.0f / 1080.0f);
    std::vector<double> first(variants.size()), second(variants.size()), psnr(variants.size(), 0.0);
    std::vector<nlohmann::json> lodInfo(variants.size());
    std::vector<float> offTransparent, offOpaque;
    for (int pass = 0; pass < 2; ++pass)
        for (std::size_t k = 0; k < variants.size(); ++k) {
            const std::size_t i = pass == 0 ? k : variants.size() - 1 - k;
            const LodVariant& v = variants[i];
            std::unique_ptr<tc::gl::VrcRenderer> r = renderer(v, 1920, 1080);
            Frame f = frame(*r, cam, 1920, 1080);
            (pass == 0 ? first : second)[i] = f.ms;
            if (pass == 0) {
                std::vector<float>& off = v.transparent ? offTransparent : offOpaque;
                if (!v.lod)
                    off = std::move(f.images.rgba);
                else
                    psnr[i] = tc::compareRgba(f.images.rgba, off).psnr;
            }
            if (pass == 0 && v.lod) {
                r->enableLodStats();
                frame(*r, cam, 1920, 1080);
                lodInfo[i] = r->describe()["lod"];
            }
            std::fprintf(stderr, "%s: %.0f ms (load %s)\n", v.name, f.ms, loadAverage().c_str());
        }

    // PSNR against depth peeling at a smaller size of the same view (slow: minutes on the dense sets).
    std::vector<double> peelPsnr(variants.size(), 0.0);
    double peelMs = 0;
    if (psnrWidth > 0) {
        const tc::Camera small =
            tc::fitCamera(set.scene.camera, set.lines.bounds, float(psnrWidth) / float(psnrHeight));
        tc::Scene peel = set.scene;
        peel.image.width = psnrWidth;
        peel.image.height = psnrHeight;
        peel.render.technique = tc::RenderTechnique::Rasterized;
        peel.output.aovDepth = peel.output.aovNormal = peel.output.aovId = false;
        peel.render.transparency = tc::Transparency::DepthPeeling;
        const auto start = Clock::now();
        const Frame peelTransparent = renderOnce(peel, transparentLines, small);
        peelMs = msSince(start);
        peel.render.transparency = tc::Transparency::Opaque;
        const Frame exactOpaque = renderOnce(peel, set.lines, small);
        for (std::size_t i = 0; i < variants.size(); ++i) {
            std::unique_ptr<tc::gl::VrcRenderer> r = renderer(variants[i], psnrWidth, psnrHeight);
            const Frame f = frame(*r, small, psnrWidth, psnrHeight);
            peelPsnr[i] = tc::compareRgba(f.images.rgba, variants[i].transparent ? peelTransparent.images.rgba
                                                                                 : exactOpaque.images.rgba)
                              .psnr;
        }
    }

    std::printf(
        "\n%s (%zu segments), 1920x1080, VRC resolution %d, quantization %d, transparent at opacity 0.3; "
        "frame ms (in order, reverse); PSNR at 1080p against the same mode without LoD%s; load %s\n\n",
        set.name.c_str(), set.lines.segmentCount(), options.resolution, options.quantization,
        psnrWidth > 0
            ? (", and at " + std::to_string(psnrWidth) + "x" + std::to_string(psnrHeight) +
               " against depth peeling / rasterized opaque (depth peeling " + std::to_string(int(peelMs)) + " ms)")
                  .c_str()
            : "",
        loadAverage().c_str());
    std::printf(
        "| variant | frame ms | vs LoD off | PSNR vs LoD off (dB) |%s LoD volume MB | samples per level (%%) |\n",
        psnrWidth > 0 ? " PSNR vs exact (dB) |" : "");
    std::printf("|---|---:|---:|---:|%s---:|---|\n", psnrWidth > 0 ? "---:|" : "");
    for (std::size_t i = 0; i < variants.size(); ++i) {
        const LodVariant& v = variants[i];
        const std::size_t off = v.transparent ? 0 : 5;  // the "LoD off" row of the same mode
        const double ms = 0.5 * (first[i] + second[i]), offMs = 0.5 * (first[off] + second[off]);
        std::string levels = "-", volume = "-";
        if (v.lod && lodInfo[i].is_object()) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.1f", lodInfo[i]["volume_mb"].get<double>());
            volume = buf;
            const std::vector<double> samples = lodInfo[i]["samples_per_level"].get<std::vector<double>>();
            double total = 0;
            for (double x : samples) total += x;
            levels.clear();
            for (std::size_t l = 0; l < samples.size(); ++l)
                if (samples[l] > 0) {
                    std::snprintf(buf, sizeof buf, "%sL%zu %.0f", levels.empty() ? "" : ", ", l,
                                  100.0 * samples[l] / total);
                    levels += buf;
                }
            if (levels.empty()) levels = "none";
        }
        char peelCell[32] = "";
        if (psnrWidth > 0) std::snprintf(peelCell, sizeof peelCell, " %.1f |", peelPsnr[i]);
        std::printf("| %s | %.0f, %.0f | %.2fx | %s |%s %s | %s |\n", v.name, first[i], second[i], ms / offMs,
                    v.lod ? std::to_string(psnr[i]).substr(0, 4).c_str() : "-", peelCell, volume.c_str(),
                    levels.c_str());
        std::fflush(stdout);
    }
    if (lodInfo[1].is_object()) {
        std::printf("\nLoD levels (grid): %s\n", lodInfo[1]["level_grids"].dump().c_str());
        std::printf("LoD levels (MB): %s\n", lodInfo[1]["level_mb"].dump().c_str());
    }
}

}  // namespace

int main(int argc, char** argv) try {
    std::vector<std::size_t> segmentCounts{100000, 1000000};
    std::vector<std::size_t> quantizations{32, 0};
    int points = 501, resolution = 128, reps = 2, threads = 0;
    std::size_t frameSegments = 0;
    std::vector<std::string> setPaths;
    bool lod = false;
    int psnrWidth = 0, psnrHeight = 0;
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
        else if (flag == "--sets")
            setPaths = splitCommas(argv[i + 1]);
        else if (flag == "--lod")
            lod = std::atoi(argv[i + 1]) != 0;
        else if (flag == "--psnr-size") {
            if (std::sscanf(argv[i + 1], "%dx%d", &psnrWidth, &psnrHeight) != 2) {
                std::fprintf(stderr, "error: --psnr-size expects WxH\n");
                return 2;
            }
        } else {
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

    if (!setPaths.empty()) {
        std::vector<BenchSet> sets;
        for (const std::string& path : setPaths) sets.push_back(loadSet(path));
        if (!lod) buildTable(sets);
        for (const BenchSet& set : sets)
            if (lod) lodTable(set, psnrWidth, psnrHeight);
        return 0;
    }

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
