#pragma once
// The technique registry: one descriptor per render technique, saying what the technique takes
// (data kinds, transparency modes, ambient occlusion methods), what it costs per pixel and how to
// make it. The frame loop looks techniques up by name here and nowhere else; render.technique
// "auto" is a rule over the descriptors (resolveAuto); every combination check a user can hit
// runs here, with the usual "file: key: expectation" message (exit code 2).
//
// Descriptors live beside their techniques (gl/*, rt/*) and are listed once per library
// (gl/techniques.cpp, rt/techniques.cpp); docs/architecture.md has the recipe for adding one.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/region.h"
#include "core/scene.h"
#include "core/technique.h"

namespace tc {

struct LineSet;
struct ParticleData;
struct StyledLines;
struct OpacitySystem;

enum class DataKind { Lines, Particles };
const char* dataKindName(DataKind kind);  // "lines", "particles"

// Where a technique runs: on the GL context (gl/) or on the CPU (rt/; it needs no GL at all).
enum class TechniqueBackend { Gl, Cpu };

// The scene-file spellings of the enums the registry checks.
const char* transparencyName(Transparency t);  // "opaque", "kbuffer", ...
const char* aoMethodName(AoSpec::Method m);    // "cone_traced", "ray_traced"

// The dataset a technique is made for. Lines are styled once by the frame loop; a particle time
// series is styled frame by frame by the technique as the animation reaches each data frame
// (core/particle_series.h).
struct TechniqueData {
    DataKind kind = DataKind::Lines;
    const StyledLines* lines = nullptr;       // kind Lines
    const LineSet* source = nullptr;          // kind Lines: as read (attributes the style did not map)
    const ParticleData* particles = nullptr;  // kind Particles: every data frame
    int firstFrame = 0;                       // the first animation frame that will be rendered
    // Data-parallel rendering: draw only what enters the rays inside this box (core/region.h);
    // the data may extend beyond it. Unbounded (the default) = the whole frame.
    RegionBox region;
    // Data-parallel rendering: the bounds of the whole dataset (every rank's data) and its largest
    // tube or sphere radius, from which the AO grid, the AO cone length and the depth range
    // derive, so that they are the same on every rank and as in one process. Empty bounds / 0
    // (the defaults) = those of the data above.
    Bounds bounds;
    float maxRadius = 0;
};

// Observers the frame loop attaches (a technique never writes files itself).
struct TechniqueHooks {
    // Every frame's optimisation problem of opacity optimization (render.opacity.dump_dir).
    std::function<void(const OpacitySystem&)> opacitySystem;
    // Data-parallel rendering: replaces a density grid (the ambient occlusion volume's finest
    // level, x fastest) by the sum of every rank's, so AO sees all the data; null = as built.
    std::function<void(std::vector<float>& grid)> reduceDensity;
};

// The region part of `data` and `hooks`, as the renderers take it (core/region.h).
inline RegionSetup regionSetup(const TechniqueData& data, const TechniqueHooks& hooks) {
    RegionSetup r;
    r.box = data.region;
    r.dataBounds = data.bounds;
    r.dataMaxRadius = data.maxRadius;
    r.reduceDensity = hooks.reduceDensity;
    return r;
}

// The InputError of a technique (or a mode of one) that cannot render one region of a
// data-parallel frame: "<file>: <key>: <what> does not support data-parallel rendering (--mpi);
// supported: <supported>". Thrown by create() when TechniqueData::region is set; `tubecast render
// --mpi` refuses what the descriptors do not list before any create(), with the list made from the
// descriptors (TechniqueRegistry::requireRegions). The default is that list for the built-in
// techniques, for the renderers, which do not see the registry.
inline constexpr const char* kRegionTechniques = "rasterized (opaque, kbuffer, depth_peeling), raytraced, spheres";
[[noreturn]] void refuseRegion(const Scene& scene, const std::string& key, const std::string& what,
                               const std::string& supported = kRegionTechniques);

// Memory a GL technique allocates per pixel of its render target; tiling plans against it
// (core/tiling.h planSceneTiles). CPU techniques allocate nothing per pixel but their output.
struct PixelBuffers {
    std::size_t bytes = 0;           // every per-pixel buffer and texture together
    std::size_t largestStorage = 0;  // the largest per-pixel shader storage buffer (its GL limit)
    std::string what;                // for messages: "kbuffer with k=8"
};

// A scene key (from the root, "render.ao.method") and what is wrong with it.
struct SpecProblem {
    std::string key;
    std::string message;
};

struct TechniqueDescriptor {
    std::string name;     // the render.technique value
    std::string summary;  // one line for `tubecast techniques`
    std::string paper;    // the paper it implements ("" for none)
    TechniqueBackend backend = TechniqueBackend::Gl;
    std::vector<DataKind> data;      // what it renders
    std::vector<DataKind> autoData;  // what render.technique "auto" may choose it for
    std::vector<Transparency> transparency;
    // Its exact-order transparent mode (what a transparent scene gets when it names none).
    Transparency exactTransparency = Transparency::Opaque;
    // Modes of `transparency` the technique accepts but renders as its exact mode (a ray tracer has
    // no k-buffer): "auto" does not pick it when the scene names one of them, because the user
    // asked for that method (e.g. to reproduce a paper's k-buffer image).
    std::vector<Transparency> transparencyAliases;
    std::vector<AoSpec::Method> ao;  // empty: no ambient occlusion
    // The transparency modes in which it renders one region of a data-parallel frame
    // (TechniqueData::region, core/region.h; `tubecast render --mpi`); empty: none.
    std::vector<Transparency> regionTransparency;
    // The transparency modes in which it draws style.halo (depth-dependent halos); empty: none.
    std::vector<Transparency> halo;
    // Rules beyond the lists above (e.g. no AO with one of its modes); null = none.
    std::function<std::optional<SpecProblem>(const Scene&, DataKind)> check;
    // Per-pixel GPU memory for `scene`; null = none.
    std::function<PixelBuffers(const Scene&, DataKind)> pixelBuffers;
    // Whether a pixel is rendered independently of the others' contents, so tiles and image.samples
    // compose (core/tiling.h); null = always.
    std::function<bool(const Scene&)> composesWindows;
    // Makes the technique (after a successful check). GL techniques need a current context.
    std::function<std::unique_ptr<Technique>(const Scene&, const TechniqueData&, const TechniqueHooks&)> create;

    bool takes(DataKind kind) const;
    PixelBuffers pixelBuffersFor(const Scene& scene, DataKind kind) const;
    bool composes(const Scene& scene) const { return !composesWindows || composesWindows(scene); }
};

// What is wrong with rendering `scene` (as `kind`) with `d`, or nothing: the data kind, the
// transparency mode (any, while it is "auto"), the AO method, then the descriptor's own check.
std::optional<SpecProblem> checkTechnique(const TechniqueDescriptor& d, const Scene& scene, DataKind kind);
// The same as an InputError "file: key: message" (for renderers that guard their create()).
void requireTechnique(const TechniqueDescriptor& d, const Scene& scene, DataKind kind);

// render.transparency "auto" for technique `d`: opaque when no opacity is below 1 (`translucent`
// false), else the technique's exact-order transparent mode; `why` is the log line. With halos
// (`halo`) and a technique whose opaque mode draws none, the exact-order mode also for opaque
// lines: with every opacity 1 it composites to the nearest surface, i.e. the opaque image plus
// the halos the user asked for.
struct TransparencyChoice {
    Transparency mode = Transparency::Opaque;
    std::string why;
};
TransparencyChoice resolveTransparency(const TechniqueDescriptor& d, bool translucent, bool halo = false);

// Whether GL_RENDERER names a software rasterizer (llvmpipe, softpipe, swrast).
bool isSoftwareRasterizer(const std::string& glRenderer);

class TechniqueRegistry {
public:
    // Adds a descriptor; a duplicate name is a programming error (tc::Error Internal).
    void add(TechniqueDescriptor d);

    const TechniqueDescriptor* find(const std::string& name) const;
    const std::vector<TechniqueDescriptor>& all() const { return m_entries; }

    // The descriptor of render.technique (not "auto"), checked for `kind`. Throws InputError naming
    // the scene file and key: an unknown name (listing the registered ones), or what
    // checkTechnique finds.
    const TechniqueDescriptor& validate(const Scene& scene, DataKind kind) const;
    // Without the data (tubecast validate): the name, and the checks of at least one data kind
    // the technique takes ("auto": only that some technique takes the scene).
    void validateWithoutData(const Scene& scene) const;

    // Data-parallel rendering: "rasterized (opaque, ...), raytraced (...)", the techniques whose
    // descriptors list regionTransparency, with those modes.
    std::string regionSupport() const;
    // Throws InputError "file: render.technique: \"NAME\" does not support data-parallel rendering
    // (--mpi); supported: <regionSupport()>" (render.transparency when only the mode is missing)
    // unless render.technique renders regions in render.transparency. "auto" passes (a technique
    // "auto": any; a transparency "auto": any mode of the technique): check again once resolved.
    void requireRegions(const Scene& scene) const;

    // render.technique "auto": on a software GL rasterizer the first CPU technique (in
    // registration order) that takes the scene, else the first GL one; on a hardware GL the first
    // GL technique, else the first CPU one. Only techniques whose autoData has `kind` count.
    // `why` is the log line ("render.technique auto: raytraced (...)"). Throws InputError when
    // no technique takes the scene.
    struct AutoChoice {
        const TechniqueDescriptor* descriptor = nullptr;
        std::string why;
    };
    AutoChoice resolveAuto(const Scene& scene, DataKind kind, const std::string& glRenderer) const;

private:
    std::vector<TechniqueDescriptor> m_entries;
};

}  // namespace tc
