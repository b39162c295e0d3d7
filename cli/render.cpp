// tubecast render SCENE: the frame loop. Plans outputs (and refuses to clobber), loads and
// styles the data once, creates the GL context and technique once, then renders, composites
// and writes each frame (temp file + rename) and appends its stage timings.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <unistd.h>

#include "cli/batch.h"
#include "cli/commands.h"
#include "cli/technique_registry.h"
#include "core/animation.h"
#include "core/compositing.h"
#include "core/error.h"
#include "core/image_metrics.h"
#include "core/opacity_system.h"
#include "core/particle_series.h"
#include "core/scene.h"
#include "core/styling.h"
#include "core/technique_registry.h"
#include "core/tiling.h"
#include "gl/context.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"
#include "core/tiled_technique.h"
#include "gl/view_window.h"
#include "io/atomic_file.h"
#include "io/dataset.h"
#include "io/image_io.h"
#include "io/json_file.h"
#include "io/opacity_system_dump.h"
#include "io/paraview_preset.h"
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
    // Batch (docs/batch.md).
    std::string shard;  // "I/N" or "slurm"; empty = the whole frame list
    bool keepGoing = false;
    bool placeholders = false;
    double placeholderTimeout = 600.0;
    std::string logFormat = "human";
    bool dryRun = false;
    bool serialWrites = false;
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

// Progress: a line rewritten in place on a terminal, plain log lines otherwise (both on stderr,
// silenced by -q), or JSON lines on stdout with --log-format json (one object per event, for
// workflow tools; not silenced by -q since they were asked for). frames/s and the ETA use the
// wall clock since the first frame started, so they include writing and waiting.
class Progress {
public:
    Progress(std::size_t total, bool quiet, bool json)
        : m_total(total), m_quiet(quiet), m_json(json), m_tty(isatty(2)),
          m_start(std::chrono::steady_clock::now()) {}
    void frameDone(int frame, double seconds) { report(frame, seconds, ""); }
    void frameFailed(int frame, double seconds, const std::string& message) { report(frame, seconds, message); }
    void frameSkipped(int frame, const std::string& why) {
        ++m_done;
        if (m_json) emit({{"event", "skipped"}, {"frame", frame}, {"reason", why}});
        else if (!m_quiet) std::cerr << (m_tty ? "\r\033[K" : "") << "tubecast: frame " << frame << " skipped: " << why << "\n";
    }
    void event(nlohmann::json e) {
        if (m_json) emit(std::move(e));
    }

private:
    void report(int frame, double seconds, const std::string& error) {
        ++m_done;
        double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
        double fps = wall > 0 ? double(m_done) / wall : 0.0;
        double eta = fps > 0 ? double(m_total - m_done) / fps : 0.0;
        if (m_json) {
            nlohmann::json e = {{"event", error.empty() ? "frame" : "failed"}, {"frame", frame}, {"done", m_done},
                                {"total", m_total}, {"seconds", seconds}, {"frames_per_s", fps}, {"eta_s", eta}};
            if (!error.empty()) e["error"] = error;
            emit(std::move(e));
            return;
        }
        if (!error.empty()) {
            // Failures are never silenced: they are the frames to re-run.
            std::cerr << (m_tty ? "\r\033[K" : "") << "error: frame " << frame << ": " << error << "\n";
            return;
        }
        if (m_quiet) return;
        std::ostringstream line;
        line << "frame " << m_done << "/" << m_total << " (#" << frame << ") " << std::fixed << std::setprecision(2)
             << seconds << " s, " << fps << " frames/s, ETA " << formatSeconds(eta);
        if (m_tty) std::cerr << "\r\033[K" << line.str() << (m_done == m_total ? "\n" : "") << std::flush;
        else std::cerr << "tubecast: " << line.str() << "\n";
    }
    static void emit(nlohmann::json e) { std::cout << e.dump() << "\n" << std::flush; }

    std::size_t m_total, m_done = 0;
    bool m_quiet, m_json, m_tty;
    std::chrono::steady_clock::time_point m_start;
};

// Row-major float[16] of a glm matrix as stored (column-major), see ExrOptions::matrices.
std::array<float, 16> matrixValues(const glm::mat4& m) {
    std::array<float, 16> v{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) v[std::size_t(4 * c + r)] = m[c][r];
    return v;
}

// SLURM_JOB_ID, with the array task when there is one ("1234_5"), for placeholders and run.json.
std::string slurmJobId() {
    const char* job = std::getenv("SLURM_ARRAY_JOB_ID");
    const char* task = std::getenv("SLURM_ARRAY_TASK_ID");
    if (job && task) return std::string(job) + "_" + task;
    const char* id = std::getenv("SLURM_JOB_ID");
    return id ? id : "";
}

void runRender(const RenderOptions& o) {
    Scene scene = loadScene(o.scene, o.overrides);
    loadStylePresets(scene.style, scene.file);  // a bad preset file fails before any output
    const TechniqueRegistry& registry = techniqueRegistry();
    registry.validateWithoutData(scene);  // so does a technique that cannot take the settings
    if (!o.outDir.empty()) scene.output.dir = o.outDir;
    const OutputSpec& out = scene.output;
    const std::vector<int> selected = parseFrameList(o.frames, scene.frameCount());
    if (o.resume && o.overwrite) throw InputError("--resume and --overwrite exclude each other");
    if (o.placeholderTimeout <= 0) throw InputError("--placeholder-timeout must be > 0 seconds");
    std::optional<Shard> shard;
    if (!o.shard.empty()) shard = parseShard(o.shard, processEnv());
    const std::vector<int> frames = shard ? shardFrames(selected, *shard) : selected;
    const std::string hash = sceneHash(scene.resolved);

    // Plan every output before any work, so a conflict costs nothing and nothing is clobbered.
    // --resume re-renders a frame unless every output of it decodes completely and carries this
    // scene's hash (a killed writer cannot leave a truncated final file, but a full disk, a
    // copy or an edit of the scene can).
    ensureWritableDir(out.dir);
    std::vector<FramePlan> todo;
    std::size_t skipped = 0;
    auto frameBase = [&](int f) { return (fs::path(out.dir) / frameFileName(out.name, f)).string(); };
    auto allComplete = [&](const FramePlan& plan, std::string* why) {
        for (const auto& p : plan.paths) {
            OutputCheck c = checkFrameOutput(p, hash);
            if (c.state != OutputState::Complete) {
                if (why) *why = c.reason;
                return false;
            }
        }
        return true;
    };
    for (int f : frames) {
        FramePlan plan{f, {}};
        std::string base = frameBase(f);
        if (out.png) plan.paths.push_back(base + ".png");
        if (out.exr) plan.paths.push_back(base + ".exr");
        std::string firstExisting;
        for (const auto& p : plan.paths)
            if (fs::exists(p) && firstExisting.empty()) firstExisting = p;
        if (o.resume && !firstExisting.empty()) {
            std::string why;
            if (allComplete(plan, &why)) {
                ++skipped;
                continue;
            }
            if (!o.quiet && why != "missing") std::cerr << "tubecast: --resume: frame " << f << " re-rendered: " << why << "\n";
        }
        if (!firstExisting.empty() && !o.overwrite && !o.resume)
            throw OutputError(firstExisting + " exists; use --resume to skip finished frames or --overwrite to replace them");
        todo.push_back(plan);
    }
    // Side files per process: shards sharing a directory never write the same one.
    const std::string timingsPath = (fs::path(out.dir) / sideFileName("timings.csv", shard)).string();
    const std::string runPath = (fs::path(out.dir) / sideFileName("run.json", shard)).string();
    const std::string qualityPath = (fs::path(out.dir) / sideFileName("quality.csv", shard)).string();
    if (!o.overwrite && !o.resume && !todo.empty() && !o.dryRun)
        for (const auto& p : {timingsPath, runPath})
            if (out.timings && fs::exists(p))
                throw OutputError(p + " exists; use --resume to append or --overwrite to replace it");
    if (o.dryRun) {
        // The frames this run would render, as a --frames list on stdout (scripts/slurm/check.sh).
        std::vector<int> pending;
        for (const auto& plan : todo) pending.push_back(plan.frame);
        std::cout << formatFrameList(pending) << "\n";
        if (!o.quiet)
            std::cerr << "tubecast: --dry-run: " << pending.size() << " of " << frames.size() << " frame(s) to render, "
                      << skipped << " complete\n";
        return;
    }
    if (skipped && !o.quiet) std::cerr << "tubecast: --resume: " << skipped << " frame(s) already complete\n";
    if (todo.empty()) {
        if (!o.quiet) std::cerr << "tubecast: nothing to render\n";
        return;
    }

    // llvmpipe sizes its thread pool from the machine's CPUs when the context is created; array
    // tasks sharing a node would each start one thread per core. Give it the job's CPUs instead.
    if (auto threads = llvmpipeThreads(processEnv(), affinityCpuCount())) {
        setenv("LP_NUM_THREADS", std::to_string(threads->threads).c_str(), 1);
        if (o.verbose || (!o.quiet && std::getenv("SLURM_JOB_ID")))
            std::cerr << "tubecast: LP_NUM_THREADS=" << threads->threads << " (from " << threads->source << ")\n";
    } else if (o.verbose) {
        std::cerr << "tubecast: LP_NUM_THREADS=" << std::getenv("LP_NUM_THREADS") << " (set by the user)\n";
    }

    // Per dataset, once per process.
    auto t0 = std::chrono::steady_clock::now();
    DatasetLoad data = loadDataset(scene.dataset);
    if (data.cleaned.any()) std::cerr << "warning: " << data.source << ": " << data.cleaned.summary() << "\n";
    // Particle datasets are styled frame by frame by their technique (core/particle_series.h);
    // `styled` is empty then and only carries the spheres' bounds (camera fit, depth range).
    const DataKind kind = data.isParticles() ? DataKind::Particles : DataKind::Lines;
    const bool particles = kind == DataKind::Particles;
    StyledLines styled = particles ? StyledLines{} : styleLines(data.lines, scene.style, scene.file);
    if (particles) styled.bounds = particleSeriesBounds(scene, data.particles);
    double prepareSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    gl::ContextConfig config;
    config.backend = gl::parseBackend(o.backend);
    config.device = o.device;
    const std::optional<CudaDeviceChoice> cuda = cudaDeviceFromEnv(processEnv(), o.device);
    if (cuda) config.cudaDevice = cuda->cudaDevice;
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
    if (cuda && !o.quiet)
        std::cerr << "tubecast: " << cuda->source << ": "
                  << (context.info().cudaDevice >= 0
                          ? "CUDA device " + std::to_string(cuda->cudaDevice) + " is EGL device " + context.info().device
                          : "no EGL device reports a CUDA ordinal (EGL_NV_device_cuda), device chosen as without it")
                  << "\n";
    if (scene.render.technique.isAuto()) {
        const TechniqueRegistry::AutoChoice choice = registry.resolveAuto(scene, kind, context.info().renderer);
        scene.render.technique = RenderTechnique(choice.descriptor->name);
        if (!o.quiet) std::cerr << "tubecast: " << choice.why << "\n";
    }
    const TechniqueDescriptor& descriptor = registry.validate(scene, kind);
    // Tiles (image.tiles, or render.memory_budget_mb over the per-pixel buffers; core/tiling.h):
    // the technique renders the largest tile, wrapped to render every tile and sample.
    const PixelBuffers pixelBuffers = descriptor.pixelBuffersFor(scene, kind);
    const TilePlan tilePlan = planSceneTiles(scene, pixelBuffers.bytes, pixelBuffers.what, descriptor.composes(scene),
                                             gl::currentTileLimits(pixelBuffers.largestStorage));
    Scene techniqueScene = scene;
    techniqueScene.image.width = tilePlan.largestTileWidth;
    techniqueScene.image.height = tilePlan.largestTileHeight;
    TechniqueData techniqueData;
    techniqueData.kind = kind;
    techniqueData.lines = &styled;
    techniqueData.source = &data.lines;
    techniqueData.particles = &data.particles;
    techniqueData.firstFrame = todo.front().frame;
    TechniqueHooks hooks;
    if (!scene.render.opacity.dumpDir.empty())
        hooks.opacitySystem = [dir = scene.render.opacity.dumpDir](const OpacitySystem& s) {
            const SparseMatrixD q = s.energy->assemble();
            const Eigen::VectorXd c = s.energy->linearTerm();
            const Eigen::VectorXd lower = Eigen::VectorXd::Zero(c.size()), upper = Eigen::VectorXd::Ones(c.size());
            writeOpacitySystem(dir, s.frame, {&q, &c, s.importance, &lower, &upper, s.solution, s.displayed, s.solve});
        };
    auto technique = descriptor.create(techniqueScene, techniqueData, hooks);
    const KeptAovs keptAovs{out.exr && out.aovDepth, out.exr && out.aovNormal, out.exr && out.aovId};
    technique = wrapInTiles(std::move(technique), tilePlan, scene.image.samples, keptAovs);
    if (!o.quiet && (tilePlan.tiles.size() > 1 || scene.image.samples > 1))
        std::cerr << "tubecast: " << tilePlan.tiles.size() << " tile(s) (" << tilePlan.nx << "x" << tilePlan.ny
                  << (tilePlan.automatic ? ", for render.memory_budget_mb" : "") << "), largest "
                  << tilePlan.largestTileWidth << "x" << tilePlan.largestTileHeight << " with "
                  << (tilePlan.largestTileBytes >> 20) << " MB of per-pixel buffers, " << scene.image.samples
                  << " sample(s) per pixel\n";
    // render.reference: the same frames by depth peeling (GL) or exact ray tracing (rt/), compared
    // per frame into quality.csv.
    std::unique_ptr<Technique> reference;
    const char* referenceName = scene.render.referenceRaytraced ? "raytraced" : "depth_peeling";
    if (scene.render.referenceDepthPeeling || scene.render.referenceRaytraced) {
        Scene refScene = techniqueScene;
        if (scene.render.referenceRaytraced) {
            refScene.render.technique = RenderTechnique::Raytraced;
            refScene.render.raytracedAlphaCutoff = 1.0f;
            if (scene.render.transparency != Transparency::Opaque)
                refScene.render.transparency = Transparency::DepthPeeling;
        } else {
            refScene.render.technique = RenderTechnique::Rasterized;
            refScene.render.transparency = Transparency::DepthPeeling;
            refScene.render.maxPeelLayers = 0;
        }
        refScene.output.aovDepth = refScene.output.aovNormal = refScene.output.aovId = false;
        reference = wrapInTiles(registry.validate(refScene, kind).create(refScene, techniqueData, {}), tilePlan,
                                    scene.image.samples, {false, false, false});
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
    run["gl"] = {{"backend", info.backend}, {"device", info.device},   {"cuda_device", info.cudaDevice}, {"vendor", info.vendor},
                 {"renderer", info.renderer}, {"version", info.version}, {"extensions", info.extensions}};
    run["technique"] = technique->describe();
    run["image"] = {{"width", scene.image.width}, {"height", scene.image.height}};
    run["frames_planned"] = frames;
    run["scene_hash"] = hash;
    run["host"] = hostName();
    run["pid"] = long(getpid());
    run["job_id"] = slurmJobId();
    if (shard) run["shard"] = {{"index", shard->index}, {"count", shard->count}, {"spec", o.shard}};
    if (const char* lp = std::getenv("LP_NUM_THREADS")) run["lp_num_threads"] = lp;
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
    exr.metadata[kSceneHashKey] = hash;
    const std::map<std::string, std::string> pngText = {
        {"tubecast:version", TUBECAST_VERSION}, {"tubecast:renderer", info.renderer}, {kSceneHashKey, hash}};

    std::unique_ptr<Placeholders> placeholders;
    if (o.placeholders) placeholders = std::make_unique<Placeholders>(o.placeholderTimeout, slurmJobId());
    Progress progress(todo.size(), o.quiet, o.logFormat == "json");
    progress.event({{"event", "start"}, {"frames", todo.size()}, {"skipped_complete", skipped}, {"host", hostName()},
                    {"pid", long(getpid())}, {"shard", shard ? o.shard : ""}});
    std::vector<int> rendered, failed, heldElsewhere;
    // Writing a frame (compositing over the background, sRGB / zlib / EXR encoding, temp file +
    // rename) runs on a second thread while the next frame renders, so its mostly serial work
    // fills the cores the renderer leaves idle (docs/performance.md, M10). At most one write is in
    // flight, into the other of two reused FrameImages; frames are reported (timings.csv, progress,
    // failures) in order, as their writes finish. Not with --placeholders (one claim at a time),
    // image tiles (the memory budget was planned for one full-size frame) or --serial-writes.
    const bool overlapWrites = !o.serialWrites && !placeholders && todo.size() > 1 && tilePlan.tiles.size() <= 1;
    struct WriteDone {
        double ms;
        std::chrono::steady_clock::time_point end;
    };
    struct PendingFrame {
        int frame = 0;
        std::size_t outputs = 0;
        std::vector<TimingRow> rows;
        std::chrono::steady_clock::time_point start;
        std::future<WriteDone> write;
    };
    FrameImages buffers[2];  // reused across frames: no page faults or fresh zeroing per frame
    int nextBuffer = 0;
    std::optional<PendingFrame> pending;  // after `buffers`: its destructor waits for the write
    auto lastDone = std::chrono::steady_clock::now();
    // Reports a frame whose write finished (or failed): rows "write", "frame" (its latency: render
    // start to outputs complete) and "frame_interval" (outputs complete since the previous frame's:
    // the throughput, which overlapping writes improve while "frame" may grow).
    auto finish = [&](PendingFrame& f) {
        try {
            const WriteDone w = f.write.get();
            const double frameMs = std::chrono::duration<double, std::milli>(w.end - f.start).count();
            const double intervalMs = std::chrono::duration<double, std::milli>(w.end - lastDone).count();
            lastDone = w.end;
            f.rows.push_back({f.frame, "write", -1.0, w.ms, f.outputs});
            f.rows.push_back({f.frame, "frame", -1.0, frameMs, styled.segmentCount()});
            f.rows.push_back({f.frame, "frame_interval", -1.0, intervalMs, styled.segmentCount()});
            if (csv) csv->write(f.rows);
            rendered.push_back(f.frame);
            progress.frameDone(f.frame, frameMs / 1000.0);
        } catch (const std::exception& e) {
            if (!o.keepGoing) throw;
            failed.push_back(f.frame);
            double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - f.start).count();
            progress.frameFailed(f.frame, seconds, e.what());
        }
    };
    auto finishPending = [&] {
        if (!pending) return;
        PendingFrame f = std::move(*pending);
        pending.reset();
        finish(f);
    };
    for (const FramePlan& plan : todo) {
        if (placeholders) {
            if (auto holder = placeholders->claim(placeholderPath(frameBase(plan.frame)))) {
                heldElsewhere.push_back(plan.frame);
                progress.frameSkipped(plan.frame, "being rendered by " + *holder);
                continue;
            }
            // Another process may have finished it between planning and claiming.
            if (o.resume && allComplete(plan, nullptr)) {
                placeholders->release();
                progress.frameSkipped(plan.frame, "completed by another process");
                continue;
            }
        }
        auto frameStart = std::chrono::steady_clock::now();
        try {
            FrameSetup setup{plan.frame, cameraAtFrame(scene.animation, base, plan.frame), scene.image.width,
                                 scene.image.height};
            gl::StageTimer timer;
            FrameImages& images = buffers[nextBuffer];
            if (overlapWrites) nextBuffer ^= 1;
            technique->prepareFrame(plan.frame, timer);
            technique->render(setup, images, timer);
            const double renderSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - frameStart).count();

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
                *quality << plan.frame << "," << referenceName << "," << m.rmse << "," << m.psnr << "," << m.maxError << "\n"
                         << std::flush;
            }

            // Per-frame EXR header: the OpenEXR standard camera attributes and the render time.
            ExrOptions frameExr = exr;
            const glm::mat4 view = setup.camera.worldToCamera();
            const float far = glm::distance(setup.camera.eye, styled.bounds.center()) + styled.bounds.radius();
            frameExr.matrices["worldToCamera"] = matrixValues(view);
            frameExr.matrices["worldToNDC"] =
                matrixValues(projectionMatrix(setup.camera, aspect, std::max(1e-4f * far, 1e-7f), far) * view);
            frameExr.floats["tubecast:renderSeconds"] = float(renderSeconds);
            auto write = [&images, &pngText, paths = plan.paths, frameExr = std::move(frameExr),
                          background = scene.image.background] {
                auto writeStart = std::chrono::steady_clock::now();
                compositeUnder(images, background);
                for (const auto& path : paths) {
                    if (path.ends_with(".png")) writePng(images, path, pngText);
                    else writeExr(images, path, frameExr);
                }
                auto end = std::chrono::steady_clock::now();
                return WriteDone{std::chrono::duration<double, std::milli>(end - writeStart).count(), end};
            };
            finishPending();  // the previous frame, so frames are reported in order
            PendingFrame f{plan.frame, plan.paths.size(), std::move(rows), frameStart, {}};
            if (overlapWrites) {
                f.write = std::async(std::launch::async, std::move(write));
                pending = std::move(f);
            } else {
                std::promise<WriteDone> done;
                try {
                    done.set_value(write());
                } catch (...) {
                    done.set_exception(std::current_exception());
                }
                f.write = done.get_future();
                finish(f);
            }
        } catch (const std::exception& e) {
            // --keep-going: report the frame, write the others, exit 5 at the end. Without it the
            // first failure ends the run with its own exit code (after the write in flight, whose
            // own failure would be reported first).
            if (!o.keepGoing) {
                finishPending();
                throw;
            }
            failed.push_back(plan.frame);
            double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - frameStart).count();
            progress.frameFailed(plan.frame, seconds, e.what());
        }
        if (placeholders) placeholders->release();
    }
    finishPending();
    run["frames_rendered"] = rendered;
    run["frames_failed"] = failed;
    run["frames_held_elsewhere"] = heldElsewhere;
    if (out.timings) writeJsonFile(runPath, run);
    progress.event({{"event", "done"}, {"rendered", rendered}, {"failed", failed}, {"held_elsewhere", heldElsewhere}});
    if (!failed.empty())
        throw Error(ExitCode::FramesFailed, std::to_string(failed.size()) + " of " + std::to_string(todo.size()) +
                                                " frame(s) failed: " + formatFrameList(failed) +
                                                " (the others were written; re-run with --resume)");
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene's frames to PNG/EXR with timings");
    cmd->add_option("scene", o->scene, "Scene JSON file (docs/scene-spec.md)")->required();
    cmd->add_option("-o,--output", o->outDir, "Output directory (overrides output.dir)");
    cmd->add_option("--frames", o->frames, "Frames to render: 0..99, 0..99:5, 3,7,12..20 (inclusive; default all)");
    cmd->add_option("--set", o->overrides, "Override a scene key: key.path=value (repeatable, type-checked)");
    cmd->add_option_function<std::string>(
        "--dump-system", [o](const std::string& dir) { o->overrides.push_back("render.opacity.dump_dir=" + nlohmann::json(dir).dump()); },
        "Opacity optimization: write each frame's Q, c, g, bounds and solution into DIR (render.opacity.dump_dir)");
    cmd->add_option("--backend", o->backend, "OpenGL backend: auto (EGL device, EGL surfaceless, OSMesa), egl, osmesa")
        ->check(CLI::IsMember({"auto", "egl", "osmesa"}));
    cmd->add_option("--device", o->device,
                    "EGL device index (see the log for the list); with CUDA_VISIBLE_DEVICES or SLURM_JOB_GPUS set, "
                    "the index into that list");
    cmd->add_flag("--resume", o->resume,
                  "Skip frames whose outputs exist, decode completely and carry this scene's hash; append to timings");
    cmd->add_option("--shard", o->shard,
                    "Render entries I, I+N, I+2N, ... of the frame list: I/N (0-based) or 'slurm' (from the job array)");
    cmd->add_flag("--keep-going", o->keepGoing, "A failed frame is reported and the others are written; exit code 5");
    cmd->add_flag("--placeholders", o->placeholders,
                  "Claim each frame with a placeholder file so parallel jobs on one directory do not render it twice");
    cmd->add_option("--placeholder-timeout", o->placeholderTimeout,
                    "Seconds without a heartbeat after which another host's placeholder is stale (default 600)");
    cmd->add_option("--log-format", o->logFormat, "Progress: human (stderr) or json (JSON lines on stdout)")
        ->check(CLI::IsMember({"human", "json"}));
    cmd->add_flag("--dry-run", o->dryRun, "Print the frames that would be rendered (as a --frames list) and exit");
    cmd->add_flag("--overwrite", o->overwrite, "Replace existing outputs");
    cmd->add_flag("--serial-writes", o->serialWrites,
                  "Write each frame before rendering the next (default: the write overlaps the next frame's render)");
    cmd->add_flag("--gl-debug", o->glDebug, "KHR_debug messages to stderr");
    cmd->add_option("--shader-dir", o->shaderDir, "Read shaders from this directory first (for shader development)");
    cmd->add_flag("-v,--verbose", o->verbose, "Log backend selection and shader sources on errors");
    cmd->add_flag("-q,--quiet", o->quiet, "No progress output");
    cmd->callback([o] { runRender(*o); });
}

}  // namespace tc::cli
