// tubecast render SCENE: the frame loop. Plans outputs (and refuses to clobber), loads and
// styles the data once, creates the GL context and technique once, then renders, composites
// and writes each frame (temp file + rename) and appends its stage timings.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <unistd.h>

#include "cli/commands.h"
#include "core/animation.h"
#include "core/compositing.h"
#include "core/error.h"
#include "core/image_metrics.h"
#include "core/scene.h"
#include "core/styling.h"
#include "gl/context.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"
#include "gl/technique.h"
#include "io/atomic_file.h"
#include "io/dataset.h"
#include "io/image_io.h"
#include "io/json_file.h"
#include "io/timings_csv.h"

namespace tc::cli {

namespace fs = std::filesystem;

namespace {

struct RenderOptions {
    std::string scene;
    std::string outDir;
    std::string frames;
    std::vector<std::string> overrides;
    std::string backend = "auto";
    int device = -1;
    bool resume = false;
    bool overwrite = false;
    bool glDebug = false;
    bool verbose = false;
    bool quiet = false;
    std::string shaderDir;
};

struct FramePlan {
    int frame;
    std::vector<std::string> paths;  // one per requested format
};

std::string formatSeconds(double s) {
    std::ostringstream out;
    if (s < 60) out << std::fixed << std::setprecision(1) << s << " s";
    else if (s < 3600) out << int(s / 60) << " min " << int(std::fmod(s, 60.0)) << " s";
    else out << int(s / 3600) << " h " << int(std::fmod(s, 3600.0) / 60) << " min";
    return out.str();
}

// A progress line on a terminal (rewritten in place), plain log lines otherwise.
class Progress {
public:
    Progress(std::size_t total, bool quiet) : m_total(total), m_quiet(quiet), m_tty(isatty(2)) {}
    void frameDone(int frame, double seconds) {
        ++m_done;
        m_elapsed += seconds;
        if (m_quiet) return;
        double eta = m_elapsed / double(m_done) * double(m_total - m_done);
        std::ostringstream line;
        line << "frame " << m_done << "/" << m_total << " (#" << frame << ") " << std::fixed << std::setprecision(2)
             << seconds << " s, ETA " << formatSeconds(eta);
        if (m_tty) std::cerr << "\r\033[K" << line.str() << (m_done == m_total ? "\n" : "") << std::flush;
        else std::cerr << "tubecast: " << line.str() << "\n";
    }

private:
    std::size_t m_total, m_done = 0;
    double m_elapsed = 0;
    bool m_quiet, m_tty;
};

void runRender(const RenderOptions& o) {
    Scene scene = loadScene(o.scene, o.overrides);
    if (!o.outDir.empty()) scene.output.dir = o.outDir;
    const OutputSpec& out = scene.output;
    std::vector<int> frames = parseFrameList(o.frames, scene.frameCount());
    if (o.resume && o.overwrite) throw InputError("--resume and --overwrite exclude each other");

    // Plan every output before any work, so a conflict costs nothing and nothing is clobbered.
    ensureWritableDir(out.dir);
    std::vector<FramePlan> todo;
    std::size_t skipped = 0;
    for (int f : frames) {
        FramePlan plan{f, {}};
        std::string base = (fs::path(out.dir) / frameFileName(out.name, f)).string();
        if (out.png) plan.paths.push_back(base + ".png");
        if (out.exr) plan.paths.push_back(base + ".exr");
        std::size_t existing = 0;
        std::string firstExisting;
        for (const auto& p : plan.paths)
            if (fs::exists(p) && fs::file_size(p) > 0) {
                ++existing;
                if (firstExisting.empty()) firstExisting = p;
            }
        if (existing == plan.paths.size() && o.resume) {
            ++skipped;
            continue;
        }
        if (existing > 0 && !o.overwrite && !o.resume)
            throw OutputError(firstExisting + " exists; use --resume to skip finished frames or --overwrite to replace them");
        todo.push_back(plan);
    }
    const std::string timingsPath = (fs::path(out.dir) / "timings.csv").string();
    const std::string runPath = (fs::path(out.dir) / "run.json").string();
    if (!o.overwrite && !o.resume && !todo.empty())
        for (const auto& p : {timingsPath, runPath})
            if (out.timings && fs::exists(p))
                throw OutputError(p + " exists; use --resume to append or --overwrite to replace it");
    if (skipped && !o.quiet) std::cerr << "tubecast: --resume: " << skipped << " frame(s) already complete\n";
    if (todo.empty()) {
        if (!o.quiet) std::cerr << "tubecast: nothing to render\n";
        return;
    }

    // Per dataset, once per process.
    auto t0 = std::chrono::steady_clock::now();
    DatasetLoad data = loadDataset(scene.dataset);
    if (data.cleaned.any()) std::cerr << "warning: " << data.source << ": " << data.cleaned.summary() << "\n";
    StyledLines styled = styleLines(data.lines, scene.style, scene.file);
    double prepareSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    gl::ContextConfig config;
    config.backend = gl::parseBackend(o.backend);
    config.device = o.device;
#ifdef NDEBUG
    config.debug = o.glDebug;
#else
    config.debug = true;  // debug builds always route KHR_debug messages to the log
#endif
    config.verbose = o.verbose;
    gl::Context context = gl::Context::create(config);
    if (!o.shaderDir.empty()) gl::ShaderLibrary::instance().setOverrideDir(o.shaderDir);
    if (!o.quiet)
        std::cerr << "tubecast: " << context.info().backend
                  << (context.info().device.empty() ? "" : " (" + context.info().device + ")") << ", "
                  << context.info().renderer << ", " << styled.segmentCount() << " segments, " << todo.size()
                  << " frame(s) at " << scene.image.width << "x" << scene.image.height << "\n";
    auto technique = gl::createTechnique(scene, styled);
    // render.reference: the same frames by depth peeling, compared per frame into quality.csv.
    std::unique_ptr<gl::Technique> reference;
    if (scene.render.referenceDepthPeeling) {
        Scene refScene = scene;
        refScene.render.transparency = Transparency::DepthPeeling;
        refScene.render.maxPeelLayers = 0;
        refScene.output.aovDepth = refScene.output.aovNormal = refScene.output.aovId = false;
        reference = gl::createTechnique(refScene, styled);
    }

    const float aspect = float(scene.image.width) / float(scene.image.height);
    const Camera base = fitCamera(scene.camera, styled.bounds, aspect);

    nlohmann::json run;
    run["tubecast_version"] = TUBECAST_VERSION;
    run["scene_file"] = scene.file;
    run["scene"] = scene.resolved;
    run["dataset"] = {{"source", data.source},
                      {"polylines", data.lines.polylineCount()},
                      {"vertices", data.lines.vertexCount()},
                      {"segments", data.lines.segmentCount()},
                      {"skipped", data.cleaned.summary()},
                      {"load_and_style_s", prepareSeconds}};
    const auto& info = context.info();
    run["gl"] = {{"backend", info.backend}, {"device", info.device},   {"vendor", info.vendor},
                 {"renderer", info.renderer}, {"version", info.version}, {"extensions", info.extensions}};
    run["technique"] = technique->describe();
    run["image"] = {{"width", scene.image.width}, {"height", scene.image.height}};
    run["frames_planned"] = frames;
    {
        // The camera of the first planned frame (after fit), so other tools can match the view.
        Camera c = cameraAtFrame(scene.animation, base, todo.front().frame);
        run["camera_first_frame"] = {{"eye", {c.eye.x, c.eye.y, c.eye.z}},
                                     {"target", {c.target.x, c.target.y, c.target.z}},
                                     {"up", {c.up.x, c.up.y, c.up.z}},
                                     {"fov_deg", c.fovYDeg},
                                     {"projection", c.projection == Projection::Orthographic ? "orthographic" : "perspective"},
                                     {"ortho_height", c.orthoHeight}};
    }
    if (out.timings) writeJsonFile(runPath, run);

    std::unique_ptr<TimingsCsv> csv;
    if (out.timings) csv = std::make_unique<TimingsCsv>(timingsPath, o.resume && fs::exists(timingsPath));
    std::unique_ptr<std::ofstream> quality;
    if (reference) {
        const std::string qualityPath = (fs::path(out.dir) / "quality.csv").string();
        bool append = o.resume && fs::exists(qualityPath);
        quality = std::make_unique<std::ofstream>(qualityPath, append ? std::ios::app : std::ios::trunc);
        if (!*quality) throw OutputError(qualityPath + ": cannot open for writing");
        if (!append) *quality << "frame,reference,rmse,psnr_db,max_error\n" << std::flush;
    }

    ExrOptions exr;
    exr.depth = out.aovDepth;
    exr.normal = out.aovNormal;
    exr.id = out.aovId;
    exr.ao = out.aovAo;
    exr.metadata["tubecast:version"] = TUBECAST_VERSION;
    exr.metadata["tubecast:renderer"] = info.renderer;

    Progress progress(todo.size(), o.quiet);
    std::vector<int> rendered;
    for (const FramePlan& plan : todo) {
        auto frameStart = std::chrono::steady_clock::now();
        gl::FrameSetup setup{plan.frame, cameraAtFrame(scene.animation, base, plan.frame), scene.image.width,
                             scene.image.height};
        gl::StageTimer timer;
        FrameImages images;
        technique->render(setup, images, timer);

        std::vector<TimingRow> rows;
        for (const auto& st : timer.collect()) rows.push_back({plan.frame, st.stage, st.gpuMs, st.cpuMs, st.items});
        if (reference) {
            gl::StageTimer refTimer;
            FrameImages refImages;
            reference->render(setup, refImages, refTimer);
            double refMs = 0;
            for (const auto& st : refTimer.collect()) refMs += st.cpuMs;
            rows.push_back({plan.frame, "reference", -1.0, refMs, 0});
            ImageMetrics m = compareRgba(images.rgba, refImages.rgba);
            *quality << plan.frame << ",depth_peeling," << m.rmse << "," << m.psnr << "," << m.maxError << "\n"
                     << std::flush;
        }

        auto writeStart = std::chrono::steady_clock::now();
        compositeUnder(images, scene.image.background);
        for (const auto& path : plan.paths) {
            if (path.ends_with(".png")) writePng(images, path);
            else writeExr(images, path, exr);
        }
        double writeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - writeStart).count();

        rows.push_back({plan.frame, "write", -1.0, writeMs, plan.paths.size()});
        double frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart).count();
        rows.push_back({plan.frame, "frame", -1.0, frameMs, styled.segmentCount()});
        if (csv) csv->write(rows);
        rendered.push_back(plan.frame);
        progress.frameDone(plan.frame, frameMs / 1000.0);
    }
    run["frames_rendered"] = rendered;
    if (out.timings) writeJsonFile(runPath, run);
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene's frames to PNG/EXR with timings");
    cmd->add_option("scene", o->scene, "Scene JSON file (docs/scene-spec.md)")->required();
    cmd->add_option("-o,--output", o->outDir, "Output directory (overrides output.dir)");
    cmd->add_option("--frames", o->frames, "Frames to render: 0..99, 0..99:5, 3,7,12..20 (inclusive; default all)");
    cmd->add_option("--set", o->overrides, "Override a scene key: key.path=value (repeatable, type-checked)");
    cmd->add_option("--backend", o->backend, "OpenGL backend: auto (EGL device, EGL surfaceless, OSMesa), egl, osmesa")
        ->check(CLI::IsMember({"auto", "egl", "osmesa"}));
    cmd->add_option("--device", o->device, "EGL device index (see the log for the list)");
    cmd->add_flag("--resume", o->resume, "Skip frames whose outputs exist; append to timings.csv");
    cmd->add_flag("--overwrite", o->overwrite, "Replace existing outputs");
    cmd->add_flag("--gl-debug", o->glDebug, "KHR_debug messages to stderr");
    cmd->add_option("--shader-dir", o->shaderDir, "Read shaders from this directory first (for shader development)");
    cmd->add_flag("-v,--verbose", o->verbose, "Log backend selection and shader sources on errors");
    cmd->add_flag("-q,--quiet", o->quiet, "No progress output");
    cmd->callback([o] { runRender(*o); });
}

}  // namespace tc::cli
