// tubecast render SCENE: loads and styles the data once, makes the GL context and the technique
// (through the registry) once, then hands the planned frames to the frame loop. The parts:
// cli/render_plan.h (which frames and files), cli/run_manifest.h (run.json), cli/frame_loop.h and
// cli/frame_writer.h (render, compare, write each frame). With --mpi every rank of an MPI job runs
// this same sequence on its share of the data, each step a phase every rank must pass, and
// cli/mpi_render.h supplies what differs (the data's distribution, the region, the composite).
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string_view>

#include "cli/batch.h"
#include "cli/commands.h"
#include "cli/encode.h"
#include "cli/frame_loop.h"
#include "cli/frame_overlay.h"
#include "cli/mpi_render.h"
#include "cli/progress.h"
#include "cli/render_plan.h"
#include "cli/run_manifest.h"
#include "cli/scene_input.h"
#include "cli/technique_registry.h"
#include "core/animation.h"
#include "core/error.h"
#include "core/opacity_system.h"
#include "core/particle_series.h"
#include "core/scene.h"
#include "core/style_sources.h"
#include "core/styling.h"
#include "core/technique_registry.h"
#include "core/tiled_technique.h"
#include "core/tiling.h"
#include "gl/context.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"
#include "gl/view_window.h"
#include "io/atomic_file.h"
#include "io/dataset.h"
#include "io/frame_overlay.h"
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
    bool mpi = false;  // data-parallel over the ranks of an MPI job (cli/mpi_render.h)
};

// One step of the run: with --mpi a phase every rank passes or fails together (cli/mpi_session.h),
// else just the work.
void step(DataParallel* dp, std::string_view phase, const std::function<void()>& work) {
    if (dp)
        dp->phase(phase, work);
    else
        work();
}

// The scene, this process's frames and their outputs.
struct RenderJob {
    Scene scene;
    std::optional<DatasetLoad> data;  // a dataset given alone: read already
    std::optional<Shard> shard;
    std::vector<int> frames;  // of this process, before --resume
    std::string hash;
    OutputPlan plan;
};

void planScene(const RenderOptions& o, RenderJob& job, SceneInput input, bool writes) {
    if (o.mpi && o.placeholders)
        throw InputError("--placeholders: not with --mpi (one job renders each frame; use --resume)");
    job.scene = std::move(input.scene);
    job.data = std::move(input.data);
    Scene& scene = job.scene;
    loadStylePresets(scene.style, scene.file);             // a bad preset file fails before any output,
    techniqueRegistry().validateWithoutData(scene);        // and so does a technique that cannot take the settings
    if (o.mpi) techniqueRegistry().requireRegions(scene);  // or that cannot render a region (again once resolved)
    if (!o.outDir.empty()) scene.output.dir = o.outDir;
    // Only an EXR holds the depth / normal / id / AO AOVs: without one they are not computed (for
    // the transparent modes that is a whole G-buffer pass), and a scene that lists them hears why.
    OutputSpec& out = scene.output;
    if (!out.exr && (out.aovDepth || out.aovNormal || out.aovId || out.aovAo)) {
        if (scene.resolved.contains("output") && scene.resolved["output"].contains("aovs"))
            std::cerr << "warning: " << scene.file << ": output.aovs: only EXR files hold AOVs and output.formats has "
                      << "no \"exr\": not computed\n";
        out.aovDepth = out.aovNormal = out.aovId = out.aovAo = false;
    }
    const std::vector<int> selected = parseFrameList(o.frames, scene.frameCount());
    if (o.resume && o.overwrite) throw InputError("--resume and --overwrite exclude each other");
    if (o.placeholderTimeout <= 0) throw InputError("--placeholder-timeout must be > 0 seconds");
    if (!o.shard.empty()) job.shard = parseShard(o.shard, processEnv());
    job.frames = job.shard ? shardFrames(selected, *job.shard) : selected;
    job.hash = sceneHash(scene.resolved);
    if (!writes) return;
    if (scene.overlay.any()) requireOverlayFont(scene.overlay.font, scene.file);
    ensureWritableDir(scene.output.dir);
    // output.video is encoded anew after a resumed or overwriting run; otherwise it is an output
    // like the frames, never clobbered.
    if (out.video && !o.resume && !o.overwrite && !o.dryRun && fs::exists(videoPath(out)))
        throw OutputError(videoPath(out) + ": exists (output.video; use --overwrite to replace it or --resume)");
    PlanRequest request{job.frames, job.shard, job.hash, o.resume, o.overwrite, !o.dryRun};
    job.plan = planOutputs(scene.output, request, [&](const std::string& note) {
        if (!o.quiet) std::cerr << "tubecast: " << note << "\n";
    });
}

// With --mpi rank 0 plans the outputs (and reads a dataset given alone) and the others render its
// frames without writing.
RenderJob planJob(const RenderOptions& o, DataParallel* dp) {
    RenderJob job;
    SceneInput input = dp ? dp->loadSceneInput(o.scene, o.overrides) : loadSceneInput(o.scene, o.overrides);
    step(dp, "plan", [&] { planScene(o, job, std::move(input), dp == nullptr || dp->root()); });
    if (dp) dp->sharePlan(job.plan);
    return job;
}

// --dry-run and the cases with nothing to do; true when the run ends here.
bool reportPlanOnly(const RenderOptions& o, const RenderJob& job, bool speaks) {
    if (o.dryRun) {
        if (!speaks) return true;
        // The frames this run would render, as a --frames list on stdout (scripts/slurm/check.sh).
        std::vector<int> pending;
        for (const auto& plan : job.plan.todo) pending.push_back(plan.frame);
        std::cout << formatFrameList(pending) << "\n";
        if (!o.quiet)
            std::cerr << "tubecast: --dry-run: " << pending.size() << " of " << job.frames.size()
                      << " frame(s) to render, " << job.plan.skipped << " complete\n";
        return true;
    }
    if (job.plan.skipped && !o.quiet)
        std::cerr << "tubecast: --resume: " << job.plan.skipped << " frame(s) already complete\n";
    if (job.plan.todo.empty()) {
        if (!o.quiet) std::cerr << "tubecast: nothing to render\n";
        return true;
    }
    return false;
}

// llvmpipe sizes its thread pool from the machine's CPUs when the context is created; array
// tasks sharing a node would each start one thread per core. Give it the job's CPUs instead.
void setLlvmpipeThreads(const RenderOptions& o) {
    if (auto threads = llvmpipeThreads(processEnv(), affinityCpuCount())) {
        setenv("LP_NUM_THREADS", std::to_string(threads->threads).c_str(), 1);
        if (o.verbose || (!o.quiet && std::getenv("SLURM_JOB_ID")))
            std::cerr << "tubecast: LP_NUM_THREADS=" << threads->threads << " (from " << threads->source << ")\n";
    } else if (o.verbose) {
        std::cerr << "tubecast: LP_NUM_THREADS=" << std::getenv("LP_NUM_THREADS") << " (set by the user)\n";
    }
}

gl::Context makeContext(const RenderOptions& o) {
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
    if (cuda && !o.quiet)
        std::cerr << "tubecast: " << cuda->source << ": "
                  << (context.info().cudaDevice >= 0
                          ? "CUDA device " + std::to_string(cuda->cudaDevice) + " is EGL device " +
                                context.info().device
                          : "no EGL device reports a CUDA ordinal (EGL_NV_device_cuda), device chosen as without it")
                  << "\n";
    return context;
}

// The dataset as read, and as the techniques take it. Particle datasets are styled frame by frame
// by their technique (core/particle_series.h); `styled` is empty then and only carries the
// spheres' bounds (camera fit, depth range).
struct LoadedData {
    DatasetLoad load;
    DataKind kind = DataKind::Lines;
    StyledLines styled;
    Bounds bounds;       // of the whole styled data (with --mpi every rank's): camera fit, depth range
    double seconds = 0;  // loading and styling
};

// What the dataset holds, for the log: "20 polylines, 580 segments", "50000 particles",
// "30 frames of 800-1200 particles".
std::string describeData(const DatasetLoad& data) {
    if (!data.isParticles())
        return std::to_string(data.lines.polylineCount()) + " polylines, " + std::to_string(data.lines.segmentCount()) +
               " segments";
    std::size_t lo = data.particles.maxParticles(), hi = 0;
    for (const ParticleSet& f : data.particles.frames) {
        lo = std::min(lo, f.size());
        hi = std::max(hi, f.size());
    }
    const std::size_t frames = data.particles.frameCount();
    if (frames == 1) return std::to_string(hi) + " particles";
    return std::to_string(frames) + " frames of " +
           (lo == hi ? std::to_string(hi) : std::to_string(lo) + "-" + std::to_string(hi)) + " particles";
}

void styleData(const Scene& scene, LoadedData& d) {
    d.kind = d.load.isParticles() ? DataKind::Particles : DataKind::Lines;
    if (d.kind == DataKind::Lines)
        d.styled = styleLines(d.load.lines, scene.style, scene.file);
    else
        d.styled.bounds = particleSeriesBounds(scene, d.load.particles);
    d.bounds = d.styled.bounds;
}

// `preloaded`: the dataset given alone, read for its default scene (unless --set changed it).
LoadedData loadData(const Scene& scene, std::optional<DatasetLoad> preloaded) {
    LoadedData d;
    const auto t0 = std::chrono::steady_clock::now();
    if (preloaded && preloaded->source == scene.dataset.path && scene.dataset.generate.empty() && !scene.dataset.trace)
        d.load = std::move(*preloaded);
    else
        d.load = loadDataset(scene.dataset);
    if (d.load.cleaned.any()) std::cerr << "warning: " << d.load.source << ": " << d.load.cleaned.summary() << "\n";
    styleData(scene, d);
    d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return d;
}

// --mpi: this rank's share of the data (cli/mpi_render.h), styled; `bounds` is the whole data's.
LoadedData loadShare(DataParallel& dp, const Scene& scene, std::optional<DatasetLoad> preloaded, RankShare& share) {
    LoadedData d;
    const auto t0 = std::chrono::steady_clock::now();
    share = dp.loadShare(scene, std::move(preloaded));
    step(&dp, "style", [&] {
        d.load = std::move(share.load);
        styleData(scene, d);
        if (d.kind == DataKind::Lines) d.styled.incomingTangent = std::move(share.incomingTangents);
    });
    dp.agreeOnBounds(share, d.load, d.styled.bounds, d.styled.maxRadius);
    dp.checkShare(scene, share);
    d.bounds = share.bounds;
    d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return d;
}

// An empty dataset's frames: the background only (what every technique would draw; no technique
// needs a special case for no data).
class BackgroundOnly final : public Technique {
public:
    void render(const FrameSetup& setup, FrameImages& out, StageSink& sink) override {
        sink.begin("background");
        out.allocate(setup.width, setup.height);
        sink.end();
    }
    nlohmann::json describe() const override { return {{"technique", "none"}, {"reason", "the dataset is empty"}}; }
};

// The technique of the frames and the reference, wrapped in their tiles.
struct Techniques {
    std::unique_ptr<Technique> main, reference;
    std::string referenceName;
    std::string choice;  // render.technique / render.transparency "auto": what was chosen and why
    TilePlan tiles;
};

// render.reference: the same frames by depth peeling (GL) or exact ray tracing (rt/), compared per
// frame into quality.csv. Which technique and settings are exact is a property of the scene.
Scene referenceScene(const Scene& scene) {
    Scene ref = scene;
    if (scene.render.referenceRaytraced) {
        ref.render.technique = RenderTechnique::Raytraced;
        ref.render.raytracedAlphaCutoff = 1.0f;
        ref.render.raytracedExactSurface = true;
        if (scene.render.transparency != Transparency::Opaque) ref.render.transparency = Transparency::DepthPeeling;
    } else {
        ref.render.technique = RenderTechnique::Rasterized;
        ref.render.transparency = Transparency::DepthPeeling;
        ref.render.maxPeelLayers = 0;
    }
    ref.output.aovDepth = ref.output.aovNormal = ref.output.aovId = false;
    return ref;
}

// render.opacity.dump_dir: each frame's optimisation problem as files (io/opacity_system_dump.h).
TechniqueHooks techniqueHooks(const Scene& scene) {
    TechniqueHooks hooks;
    if (!scene.render.opacity.dumpDir.empty())
        hooks.opacitySystem = [dir = scene.render.opacity.dumpDir](const OpacitySystem& s) {
            const SparseMatrixD q = s.energy->assemble();
            const Eigen::VectorXd c = s.energy->linearTerm();
            const Eigen::VectorXd lower = Eigen::VectorXd::Zero(c.size()), upper = Eigen::VectorXd::Ones(c.size());
            writeOpacitySystem(dir, s.frame, {&q, &c, s.importance, &lower, &upper, s.solution, s.displayed, s.solve});
        };
    return hooks;
}

// Resolves render.technique and render.transparency "auto" (in `scene`), checks the technique against the data, plans
// the tiles (image.tiles, or render.memory_budget_mb over the technique's per-pixel buffers;
// core/tiling.h) and makes the technique for the largest tile, wrapped to render every tile and
// sample, and the reference.
// With --mpi (`dp`), `translucent` is every rank's answer and the technique draws the rank's region.
Techniques makeTechniques(const RenderOptions& o, Scene& scene, const LoadedData& data, bool translucent,
                          int firstFrame, const gl::ContextInfo& gl, const DataParallel* dp, const RankShare* share) {
    const TechniqueRegistry& registry = techniqueRegistry();
    Techniques t;
    auto note = [&](const std::string& why) {
        t.choice += (t.choice.empty() ? "" : "; ") + why;
        if (!o.quiet) std::cerr << "tubecast: " << why << "\n";
    };
    if (scene.render.technique.isAuto()) {
        const TechniqueRegistry::AutoChoice choice = registry.resolveAuto(scene, data.kind, gl.renderer);
        scene.render.technique = RenderTechnique(choice.descriptor->name);
        note(choice.why);
    }
    if (const TechniqueDescriptor* d = registry.find(scene.render.technique.name());
        d && scene.render.transparency == Transparency::Auto) {
        const TransparencyChoice choice = resolveTransparency(*d, translucent, scene.style.halo.enabled);
        scene.render.transparency = choice.mode;
        note(choice.why);
    } else if (scene.render.transparency == Transparency::Opaque && translucent) {
        std::cerr << "warning: " << scene.file
                  << ": render.transparency: \"opaque\" draws every opacity below 1 as 1 (leave the key out, or "
                     "\"auto\", for the exact transparent mode)\n";
    }
    const TechniqueDescriptor& descriptor = registry.validate(scene, data.kind);
    if (dp) dp->checkScene(scene, registry);
    const PixelBuffers buffers = descriptor.pixelBuffersFor(scene, data.kind);
    t.tiles = planSceneTiles(scene, buffers.bytes, buffers.what, descriptor.composes(scene),
                             gl::currentTileLimits(buffers.largestStorage));
    Scene techniqueScene = scene;
    techniqueScene.image.width = t.tiles.largestTileWidth;
    techniqueScene.image.height = t.tiles.largestTileHeight;

    TechniqueData input;
    input.kind = data.kind;
    input.lines = &data.styled;
    input.source = &data.load.lines;
    input.particles = &data.load.particles;
    input.firstFrame = firstFrame;
    TechniqueHooks hooks = techniqueHooks(scene);
    // Opaque ranks are Z-composited: every technique must give its depth.
    const bool depthComposite = dp && scene.render.transparency == Transparency::Opaque;
    if (dp) {
        dp->applyRegion(*share, input, hooks);
        if (depthComposite) techniqueScene.output.aovDepth = true;
    }
    // What the frame's readers take (an EXR's channels, planScene clears them without one; the
    // depth composite): what the technique is asked for, gives (it may leave the others empty,
    // rt/raytraced_renderer.h) and the tiles keep.
    const KeptAovs kept = techniqueScene.output.keptAovs();
    const bool empty = data.kind == DataKind::Lines && data.load.lines.polylineCount() == 0;
    // A technique whose pixels depend on each other takes image.samples itself (opacity
    // optimization: one solve per frame, every sample blended with its opacities).
    const int wrappedSamples = descriptor.composes(scene) ? scene.image.samples : 1;
    t.main = wrapInTiles(empty ? std::make_unique<BackgroundOnly>() : descriptor.create(techniqueScene, input, hooks),
                         t.tiles, wrappedSamples, kept);
    if (!o.quiet && (t.tiles.tiles.size() > 1 || scene.image.samples > 1))
        std::cerr << "tubecast: " << t.tiles.tiles.size() << " tile(s) (" << t.tiles.nx << "x" << t.tiles.ny
                  << (t.tiles.automatic ? ", for render.memory_budget_mb" : "") << "), largest "
                  << t.tiles.largestTileWidth << "x" << t.tiles.largestTileHeight << " with "
                  << (t.tiles.largestTileBytes >> 20) << " MB of per-pixel buffers, " << scene.image.samples
                  << " sample(s) per pixel\n";
    if ((scene.render.referenceDepthPeeling || scene.render.referenceRaytraced) && !empty) {
        const Scene ref = referenceScene(techniqueScene);
        t.referenceName = scene.render.referenceRaytraced ? "raytraced" : "depth_peeling";
        t.reference = wrapInTiles(registry.validate(ref, data.kind).create(ref, input, {}), t.tiles,
                                  scene.image.samples, {false, false, false});
    }
    return t;
}

// --mpi: the job's MpiSession, after which only rank 0 speaks (`o` made quiet on the others).
// Without --mpi, a warning when an MPI launcher started this process anyway.
std::unique_ptr<DataParallel> startDataParallel(RenderOptions& o) {
    if (!o.mpi) {
        if (MpiSession::launchedByMpi() && !o.quiet)
            std::cerr << "warning: started by an MPI launcher without --mpi: every process renders and writes the "
                         "whole frame\n";
        return nullptr;
    }
    auto dp = std::make_unique<DataParallel>(o.quiet);
    if (!dp->root()) {  // rank 0 speaks for the job
        o.quiet = true;
        o.logFormat = "human";
    }
    return dp;
}

// The log lines of the context, the data and where the style comes from.
void logSetup(const RenderOptions& o, const Scene& scene, const gl::ContextInfo& info, const LoadedData& data,
              std::size_t frames, bool mpi, const std::vector<std::string>& sources) {
    if (o.quiet) return;
    std::cerr << "tubecast: " << info.backend << (info.device.empty() ? "" : " (" + info.device + ")") << ", "
              << info.renderer << ", " << describeData(data.load) << (mpi ? " on rank 0" : "") << ", " << frames
              << " frame(s) at " << scene.image.width << "x" << scene.image.height << "\n";
    std::cerr << "tubecast: style:";
    for (std::size_t i = 0; i < sources.size(); ++i) std::cerr << (i ? "; " : " ") << sources[i];
    std::cerr << "\n";
}

// run.json before the first frame (written by the caller). With --mpi collective: the ranks'
// counts are gathered.
RunManifest startManifest(const RenderOptions& o, const RenderJob& job, const LoadedData& data,
                          const gl::ContextInfo& info, const Techniques& techniques,
                          const std::vector<std::string>& sources, const Camera& firstCamera, DataParallel* dp,
                          const RankShare& share) {
    RunManifest manifest(job.scene, job.hash);
    manifest.setDataset(dp ? share.dataset : datasetSummary(data.load), data.seconds);
    manifest.setGl(info);
    manifest.setTechnique(techniques.main->describe(), techniques.choice);
    manifest.setStyleSources(sources);
    manifest.setFrames(job.frames, job.shard, o.shard);
    manifest.setFirstCamera(firstCamera);
    if (dp) manifest.setDataParallel(dp->manifest(data.load, share.items));
    return manifest;
}

// The files the frame loop appends to besides the frames: timings.csv (`timings`: this process
// writes it), quality.csv (with a reference) and the placeholders' claims.
struct RunFiles {
    std::unique_ptr<TimingsCsv> csv;
    std::unique_ptr<std::ofstream> quality;
    std::unique_ptr<Placeholders> placeholders;
};

RunFiles openRunFiles(const RenderOptions& o, const RenderJob& job, const Techniques& techniques, bool timings,
                      bool mpi) {
    RunFiles f;
    const std::string& timingsPath = job.plan.timingsPath;
    if (timings) f.csv = std::make_unique<TimingsCsv>(timingsPath, o.resume && fs::exists(timingsPath), mpi);
    if (techniques.reference) {
        const std::string& path = job.plan.qualityPath;
        const bool append = o.resume && fs::exists(path);
        f.quality = std::make_unique<std::ofstream>(path, append ? std::ios::app : std::ios::trunc);
        if (!*f.quality) throw OutputError(path + ": cannot open for writing");
        if (!append) *f.quality << "frame,reference,rmse,psnr_db,max_error\n" << std::flush;
    }
    if (o.placeholders) f.placeholders = std::make_unique<Placeholders>(o.placeholderTimeout, slurmJobId(processEnv()));
    return f;
}

// What the frame loop needs (the pointers stay the caller's).
struct LoopParts {
    const Techniques* techniques;
    gl::StageTimer *timer, *referenceTimer;
    RunFiles* files;
    Progress* progress;
    std::function<Camera(int)> camera;
};

FrameLoopInputs frameLoopInputs(const RenderOptions& o, const RenderJob& job, const LoadedData& data,
                                const gl::ContextInfo& info, const LoopParts& parts, DataParallel* dp,
                                const RankShare& share) {
    const Scene& scene = job.scene;
    const OutputSpec& out = scene.output;
    FrameLoopInputs in;
    in.technique = parts.techniques->main.get();
    in.timer = parts.timer;
    in.reference = parts.techniques->reference.get();
    in.referenceTimer = parts.referenceTimer;
    in.referenceName = parts.techniques->referenceName;
    in.quality = parts.files->quality.get();
    in.camera = parts.camera;
    in.width = scene.image.width;
    in.height = scene.image.height;
    in.bounds = data.bounds;
    if (in.bounds.empty()) in.bounds.extend(glm::vec3(0.0f), 1.0f);  // an empty dataset: any finite depth range
    in.background = scene.image.background;
    in.pngText = {
        {"tubecast:version", TUBECAST_VERSION}, {"tubecast:renderer", info.renderer}, {kSceneHashKey, job.hash}};
    in.exr.depth = out.aovDepth;
    in.exr.normal = out.aovNormal;
    in.exr.id = out.aovId;
    in.exr.ao = out.aovAo;
    in.exr.metadata = in.pngText;
    in.csv = parts.files->csv.get();
    in.placeholders = parts.files->placeholders.get();
    in.progress = parts.progress;
    in.items = data.kind == DataKind::Lines ? data.styled.segmentCount() : data.load.particles.maxParticles();
    if (dp) {
        in.items = share.items;
        in.gatherRows = [dp](std::vector<TimingRow> rows) { return dp->gatherRows(std::move(rows)); };
    }
    in.keepGoing = o.keepGoing;
    // Not with --placeholders (one claim at a time), image tiles (the memory budget was planned for
    // one full-size frame) or --serial-writes.
    in.overlapWrites = !o.serialWrites && !parts.files->placeholders && job.plan.todo.size() > 1 &&
                       parts.techniques->tiles.tiles.size() <= 1;
    in.resume = o.resume;
    in.sceneHash = job.hash;
    if (!dp || dp->root()) {
        in.overlay = makeFrameOverlay(scene, data.load, [&o](const std::string& why) {
            if (!o.quiet) std::cerr << "tubecast: " << why << "\n";
        });
        in.overlayInExr = scene.overlay.inExr;
    }
    return in;
}

// The outcome in run.json and the progress log; failed frames are the run's error (with --mpi
// every rank knows the outcome, rank 0 reports it for the job).
void finishRun(const FrameLoopOutcome& outcome, const RenderJob& job, RunManifest& manifest, bool timings,
               Progress& progress, DataParallel* dp) {
    manifest.setOutcome(outcome.rendered, outcome.failed, outcome.heldElsewhere);
    if (timings) manifest.write(job.plan.runPath);
    progress.event({{"event", "done"},
                    {"rendered", outcome.rendered},
                    {"failed", outcome.failed},
                    {"held_elsewhere", outcome.heldElsewhere}});
    step(dp, "frames", [&] {
        if (!outcome.failed.empty() && (!dp || dp->root()))
            throw Error(ExitCode::FramesFailed, std::to_string(outcome.failed.size()) + " of " +
                                                    std::to_string(job.plan.todo.size()) +
                                                    " frame(s) failed: " + formatFrameList(outcome.failed) +
                                                    " (the others were written; re-run with --resume)");
    });
}

// output.video after the run: when every frame of the scene has its PNG (an unsharded run that
// completed the scene, or resumed one to completion). A shard's run leaves it to
// `tubecast encode` after the last shard (docs/batch.md).
void encodeAfterRun(const RenderOptions& o, const RenderJob& job, bool root) {
    const OutputSpec& out = job.scene.output;
    if (!out.video || !root || o.dryRun) return;
    if (job.shard) {
        if (!o.quiet)
            std::cerr << "tubecast: output.video: a shard does not encode; after the last shard run: tubecast encode "
                      << out.dir << " " << videoPath(out) << "\n";
        return;
    }
    std::vector<int> all;
    for (int f = 0; f < job.scene.frameCount(); ++f) all.push_back(f);
    std::vector<std::string> pngs;
    try {
        pngs = framePngs(out.dir, out.name, all);
    } catch (const InputError& e) {
        if (!o.quiet) std::cerr << "tubecast: output.video: not encoded yet: " << e.what() << "\n";
        return;
    }
    encodeVideo(pngs, videoPath(out), out.video->fps, out.video->crf, o.quiet);
}

// The run, in its named parts: the plan, the data, the context and technique, run.json and
// the run's files, the frame loop, the outcome.
void runRender(const RenderOptions& options) {
    RenderOptions o = options;
    const std::unique_ptr<DataParallel> dp = startDataParallel(o);
    const bool root = !dp || dp->root();
    RenderJob job = planJob(o, dp.get());
    if (reportPlanOnly(o, job, root)) {
        encodeAfterRun(o, job, root);  // --resume of a complete run without its movie
        return;
    }
    Scene& scene = job.scene;
    const std::vector<FramePlan>& todo = job.plan.todo;
    setLlvmpipeThreads(o);

    RankShare share;
    const LoadedData data = dp ? loadShare(*dp, scene, std::move(job.data), share)
                               : loadData(scene, std::move(job.data));  // per dataset, once per process
    if (!dp && data.kind == DataKind::Lines && data.load.lines.polylineCount() == 0)
        std::cerr << "warning: " << data.load.source << ": the dataset holds no polylines: the frames show the "
                  << "background only\n";
    std::optional<gl::Context> context;
    step(dp.get(), "context", [&] { context = makeContext(o); });
    const gl::ContextInfo& info = context->info();
    const std::vector<std::string> sources =
        styleSources(scene.style, data.kind == DataKind::Particles ? &data.load.particles : nullptr);
    logSetup(o, scene, info, data, todo.size(), dp != nullptr, sources);
    bool translucent =
        data.kind == DataKind::Lines ? anyTranslucent(data.styled) : anyTranslucent(scene.style, data.load.particles);
    if (dp) translucent = dp->any(translucent);
    Techniques techniques;
    step(dp.get(), "technique",
         [&] { techniques = makeTechniques(o, scene, data, translucent, todo.front().frame, info, dp.get(), &share); });
    if (dp) techniques.main = dp->composited(std::move(techniques.main), scene, share);

    const Camera base = fitCamera(scene.camera, data.bounds, float(scene.image.width) / float(scene.image.height));
    const auto camera = [&](int frame) { return cameraAtFrame(scene.animation, base, frame); };
    RunManifest manifest =
        startManifest(o, job, data, info, techniques, sources, camera(todo.front().frame), dp.get(), share);
    const bool timings = scene.output.timings && root;
    if (timings) manifest.write(job.plan.runPath);
    RunFiles files = openRunFiles(o, job, techniques, timings, dp != nullptr);
    Progress progress(todo.size(), o.quiet, o.logFormat == "json", std::cerr, std::cout, isatty(2));
    progress.event({{"event", "start"},
                    {"frames", todo.size()},
                    {"skipped_complete", job.plan.skipped},
                    {"host", hostName()},
                    {"pid", long(getpid())},
                    {"shard", job.shard ? o.shard : ""}});

    gl::StageTimer timer, referenceTimer;
    const LoopParts parts{&techniques, &timer, &referenceTimer, &files, &progress, camera};
    const FrameLoopOutcome outcome =
        runFrameLoop(todo, scene.output, frameLoopInputs(o, job, data, info, parts, dp.get(), share));
    finishRun(outcome, job, manifest, timings, progress, dp.get());
    encodeAfterRun(o, job, root);
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene's frames to PNG/EXR with timings");
    cmd->add_option("scene", o->scene,
                    "Scene JSON file (docs/scene-spec.md), or a dataset file alone: its default scene "
                    "(`tubecast scene DATASET` prints it)")
        ->required();
    cmd->add_option("-o,--output", o->outDir, "Output directory (overrides output.dir)");
    cmd->add_option("--frames", o->frames, "Frames to render: 0..99, 0..99:5, 3,7,12..20 (inclusive; default all)");
    cmd->add_option("--set", o->overrides, "Override a scene key: key.path=value (repeatable, type-checked)");
    cmd->add_option_function<std::string>(
        "--dump-system",
        [o](const std::string& dir) {
            o->overrides.push_back("render.opacity.dump_dir=" + nlohmann::json(dir).dump());
        },
        "Opacity optimization: write each frame's Q, c, g, bounds and solution into DIR (render.opacity.dump_dir)");
    cmd->add_option("--backend", o->backend, "OpenGL backend: auto (EGL device, EGL surfaceless, OSMesa), egl, osmesa")
        ->check(CLI::IsMember({"auto", "egl", "osmesa"}));
    cmd->add_option("--device", o->device,
                    "EGL device index (see the log for the list); with CUDA_VISIBLE_DEVICES or SLURM_JOB_GPUS set, "
                    "the index into that list");
    cmd->add_flag("--resume", o->resume,
                  "Skip frames whose outputs exist, decode completely and carry this scene's hash; append to timings");
    cmd->add_option(
        "--shard", o->shard,
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
    cmd->add_flag("--mpi", o->mpi,
                  "Data-parallel: every rank of the MPI job (mpirun -np N) renders its region of a k-d decomposition "
                  "of the data and IceT composites the frame; rank 0 writes the outputs (docs/batch.md)");
    cmd->add_flag("--serial-writes", o->serialWrites,
                  "Write each frame before rendering the next (default: the write overlaps the next frame's render)");
    cmd->add_flag("--gl-debug", o->glDebug, "KHR_debug messages to stderr");
    cmd->add_option("--shader-dir", o->shaderDir, "Read shaders from this directory first (for shader development)");
    cmd->add_flag("-v,--verbose", o->verbose, "Log backend selection and shader sources on errors");
    cmd->add_flag("-q,--quiet", o->quiet, "No progress output");
    cmd->callback([o] { runRender(*o); });
}

}  // namespace tc::cli
