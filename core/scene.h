#pragma once
// Scene spec v1: the typed, validated form of a scene JSON file (docs/scene-spec.md).
#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/billboard.h"
#include "core/camera.h"
#include "core/colormap.h"
#include "core/frame_images.h"
#include "core/overlay.h"

namespace tc {

// dataset.trace: streamlines of a vector field on a VTK grid (io/stream_tracer.h).
struct TraceSpec {
    std::string vector;                     // a 3-component point array, or
    std::array<std::string, 3> components;  // three scalar point arrays (x, y, z)
    enum class Seeding { Random, Uniform, Line } seeding = Seeding::Random;
    int seeds = 100;                         // seed count (uniform: about this many, on a grid)
    glm::vec3 lineFrom{0.0f}, lineTo{0.0f};  // seeding "line"
    float maxLength = 0;                     // per streamline and direction; 0 = the grid's diagonal
    enum class Direction { Forward, Backward, Both } direction = Direction::Both;
    float stepLength = 0.2f;  // integration step, in cell lengths
    int maxSteps = 2000;
    std::uint32_t randomSeed = 1;
};

struct DatasetSpec {
    std::string path;      // a file (resolved relative to the scene file), or
    std::string generate;  // a built-in generator: generatorNames() (core/generators.h) or "droplets"
    int lines = 200;       // generator parameters
    int points = 100;
    int particles = 50000;  // "droplets": particle count
    std::uint32_t seed = 1;
    int frame = -1;                  // dataset.frame: pinned data frame of a time series; -1 = follow the animation
    std::optional<TraceSpec> trace;  // dataset.trace: streamlines traced through the grid at `path`
};

// A value range for attribute mappings: explicit, "auto" (the attribute's min/max), or
// {"percentiles": [p_lo, p_hi]} of the attribute's finite values (automatic, percentiles set).
struct RangeSpec {
    bool automatic = true;
    float lo = 0.0f, hi = 1.0f;
    bool percentiles = false;
    float percentileLo = 0.0f, percentileHi = 100.0f;  // in [0, 100]
};

// style.radius: a constant, or an attribute mapped linearly from `range` to `radius_range`.
// Every style entry knows whether the scene stated it (`fromScene`, also through --set): what the
// scene states wins over radii and colours the data carries or implies (docs/scene-spec.md,
// "Precedence"); the defaults lose to them.
struct RadiusSpec {
    bool fromScene = false;
    float constant = 0.01f;
    std::string attribute;  // empty = constant
    RangeSpec range;
    float radiusLo = 0.005f, radiusHi = 0.02f;
};

// style.color: a constant sRGB colour, or an attribute through a colormap.
struct ColorSpec {
    bool fromScene = false;
    // "direction": direction-encoded colour, RGB = (|dx|, |dy|, |dz|) of the unit line tangent
    // (the tractography convention, Pajevic & Pierpaoli 1999); lines only.
    bool direction = false;
    glm::vec3 constant{0.85f, 0.55f, 0.25f};  // sRGB
    std::string attribute;
    std::string colormap = "viridis";        // a built-in name, or a ParaView preset .json (path resolved)
    std::shared_ptr<const Colormap> preset;  // loaded preset file (io/paraview_preset.h loadStylePresets)
    std::optional<glm::vec3> nanColor;       // sRGB; else the preset's NanColor, else grey 0.5
    RangeSpec range;
};

// style.opacity: a constant, or an attribute through a piecewise linear transfer function over
// the normalised attribute value t in [0,1]: points [[t0, a0], [t1, a1], ...], t ascending.
struct OpacitySpec {
    bool fromScene = false;
    float constant = 1.0f;
    std::string attribute;
    RangeSpec range;
    std::vector<glm::vec2> points{{0.0f, 0.0f}, {1.0f, 1.0f}};
    bool pointsFromColormap = false;  // "points": "colormap": the preset's opacity "Points"
};

// style.halo: depth-dependent halos around the lines (Everts et al. 2009, which Günther, Rössl &
// Theisel 2013, Sect. 4.2 draw their lines with). The halo is a ring around each tube's
// silhouette, `width` tube radii wide; its depth grows linearly from the tube's axis depth at the
// silhouette to `depth` tube radii behind it at the ring's outer edge, so it hides what lies
// further behind and not a line at about the same depth (a bundle stays one band).
struct HaloSpec {
    bool enabled = false;
    float width = 0.5f;              // ring width, in tube radii (the strip width scales with the line)
    float depth = 4.0f;              // depth offset at the ring's outer edge, in tube radii
    std::optional<glm::vec3> color;  // sRGB; unset: the complement of image.background (1 - rgb)
};

struct StyleSpec {
    RadiusSpec radius;
    ColorSpec color;
    OpacitySpec opacity;
    HaloSpec halo;
};

// The halo's sRGB colour: style.halo.color, else the complement of the background's.
glm::vec3 haloColor(const HaloSpec& halo, const glm::vec4& background);

struct CameraSpec {
    Camera camera;
    bool fit = false;  // frame the data's bounding sphere, keeping the view direction given
};

struct Keyframe {
    int frame = 0;
    glm::vec3 eye{0.0f}, target{0.0f}, up{0.0f, 1.0f, 0.0f};
};

struct AnimationSpec {
    enum class Type { None, Orbit, Keyframes } type = Type::None;
    int frames = 1;
    glm::vec3 axis{0.0f, 1.0f, 0.0f};
    float degrees = 360.0f;
    std::vector<Keyframe> keys;  // sorted by frame
};

struct ImageSpec {
    int width = 640;
    int height = 480;
    glm::vec4 background{0.0f};  // sRGB colour, straight alpha
    int tilesX = 0, tilesY = 0;  // image.tiles [nx, ny]; 0 = "auto" (by render.memory_budget_mb; core/tiling.h)
    int samples = 1;             // image.samples: jittered sub-pixel samples per pixel (core/tiling.h)
};

// render.technique: "auto" or the name of a registered technique (core/technique_registry.h).
// The scene parser takes any name; the registry checks it against what is registered, so adding
// a technique needs no change here. The constants name the built-in techniques for code that
// builds scenes (tests, benchmarks); "auto" is resolved by TechniqueRegistry::resolveAuto.
class RenderTechnique {
public:
    RenderTechnique() = default;
    explicit RenderTechnique(std::string name) : m_name(std::move(name)) {}
    const std::string& name() const { return m_name; }
    bool isAuto() const { return m_name == "auto"; }
    friend bool operator==(const RenderTechnique&, const RenderTechnique&) = default;

    static const RenderTechnique Auto, Rasterized, Raytraced, Spheres, VoxelRaycast;

private:
    std::string m_name = "rasterized";
};
// For test failure messages (gtest prints through operator<<).
std::ostream& operator<<(std::ostream& out, const RenderTechnique& t);

// Auto (the scene file's default): opaque when every opacity is 1, else the technique's exact-order
// transparent mode (TechniqueRegistry::resolveTransparency). Techniques never see Auto.
enum class Transparency { Opaque, ObjectOrder, KBuffer, DepthPeeling, OpacityOptimization, Auto };

// Where the rasterized path builds each segment's billboard: a compute pre-pass (default), the
// vertex shader (vertex pulling, once per quad corner) or a geometry shader (the paper's layout).
enum class BillboardPath { Compute, Vertex, Geometry };

// render.ao: voxel cone traced ambient occlusion from a line density volume (Groß & Gumhold 2020,
// Sect. 5.3), shared by every technique that shades surfaces.
struct AoSpec {
    bool enabled = false;
    // cone_traced: the density volume above (GL and CPU); ray_traced: `samples` stratified
    // hemisphere rays up to `distance` (raytraced technique only).
    enum class Method { ConeTraced, RayTraced } method = Method::ConeTraced;
    int samples = 16;
    int resolution = 256;  // voxels along the longest axis of the data
    int cones = 3;
    float apertureDeg = 50;  // full apex angle of each cone, 10..90
    float distance = 0.25f;  // cone length as a fraction of the bounding-box diagonal
    float strength = 1;
    // "precomputed": the cone traced AO evaluated once per data set (frame) and interpolated per
    // fragment — rasterized lines at samples along each segment (gl/ao_line_cache.h), spheres as
    // an ambient cube per sphere (gl/sphere_ambient.h); "none" traces cones per shaded point.
    // Other techniques always trace per shaded point.
    enum class Cache { Precomputed, None } cache = Cache::Precomputed;
};

// render.culling: draw the sorted segments in depth slices and skip what is already hidden
// (Groß & Gumhold 2020, Sect. 4.3): a max-depth pyramid (opaque) or a min-opacity pyramid
// (transparent) rebuilt after each slice, tested per billboard and per fragment.
struct CullingSpec {
    bool enabled = false;
    int slices = 10;
    float opacityThreshold = 0.95f;  // transparent: cull behind accumulated opacity above this
    // Opaque: the draw order is re-sorted only when the camera turns by more than this angle
    // around the data's centre or its eye moves by more than this fraction of its distance.
    float resortAngleDeg = 10.0f;
    float resortDistance = 0.1f;
};

// render.opacity: opacity optimization (Günther, Rössl & Theisel 2013; core/opacity_optimization.h).
struct OpacityOptimizationSpec {
    int segmentsPerLine = 8;                             // parts per polyline, each with one optimised opacity
    float p = 1, q = 1, r = 0.1f, s = 0.3f, lambda = 1;  // r defaults to q / 10
    enum class Importance { Constant, Length, Curvature, Attribute } importance = Importance::Constant;
    std::string attribute;           // Importance::Attribute: averaged over each part
    float rangeLo = 0, rangeHi = 1;  // mapped to importance 0..1
    float blend = 1;                 // per frame, displayed opacities move this fraction toward the solution
    float tolerance = 1e-4f;         // solver stop: projected-gradient max norm
    int maxIterations = 200;
    float dropBelow = 0;  // sparsification: h_ij below this are left out of the energy
    // How products with H are formed: H assembled (Algorithm 1's pairs), or straight from the
    // fragment lists by prefix sums (core/fragment_occlusion.h); auto picks by the pair count.
    enum class Occlusion { Auto, Assembled, Fragments } occlusion = Occlusion::Auto;
    // h_ij from the lists of every (1/scale)-th pixel in x and y (core/occlusion_matrix.h,
    // subsampleLists); the image is still resolved at full size from all lists.
    float occlusionScale = 1;
    // > 0: each frame's solve starts from the solution of the system of the lists subsampled at
    // this scale (< occlusionScale), itself started from the previous frame's solution. 0: off.
    float coarseScale = 0;
    std::string dumpDir;  // debug: write Q, c, g, bounds and the solution of each frame here
    // Assemble and solve on a worker thread while frames keep coming; displayed opacities fade
    // toward the latest finished solution (Günther et al. 2013, Sect. 4.4).
    bool pipeline = false;
};

// render.spheres: particles as transparent sphere glyphs (Staib, Grottel & Gumhold 2015).
// Density models of Sect. 4: constant (Eq. 14-15), squared distance to the centre (Eq. 16-19)
// and their hollow variants with an empty inner sphere (Sect. 4.3).
enum class SphereDensity { Constant, L2, HollowConstant, HollowL2 };

// render.spheres.ambient_opacity / ambient_emission: the ambient transfer functions of Staib et
// al. 2015, Sect. 3.2 (absorption tau_A and emission e_A of the rays that gather A_O and L_A,
// adjustable independently of the primary ones), applied when the spheres are classified into the
// ambient volume (Sect. 5). Both are piecewise linear over the particle opacity Theta_i (the
// primary transfer function's only per-particle scale): [[Theta, value], ...], Theta ascending,
// values in [0, 1]; `opacity` gives the opacity Theta_A the particle deposits, `emission` the factor
// on its colour. Empty = the primary transfer function (Theta_A = Theta_i, colour unchanged).
struct AmbientTransfer {
    static constexpr int kMaxPoints = 16;  // uniform arrays of shaders/sphere_voxelize.comp
    std::vector<glm::vec2> opacity, emission;
};

struct SpheresSpec {
    SphereDensity density = SphereDensity::Constant;
    float innerRadius = 0.5f;       // hollow models: inner radius as a fraction of the radius, [0, 0.99]
    float alphaRv = 0.5f;           // Eq. 2: weight of the volume emission (colour) vs. the surface term
    float alphaA = 0.5f;            // Eq. 7: weight of the coloured ambient light L_A (with render.ao)
    int chunks = 20;                // Sect. 5.2: early-z chunks of the sorted particles; 1 = off
    float earlyZThreshold = 0.99f;  // pixels with alpha above this are skipped by later chunks
    bool earlyZStats = false;       // count the skipped fragments (an extra rasterization pass)
    bool points = true;             // one point sprite per particle ("points"), else two triangles ("quads")
    AmbientTransfer ambient;        // Sect. 3.2: tau_A and e_A of the ambient volume
};

// render.vrc: voxel-based line ray casting (Kanzler, Rautenhaus & Westermann 2019; core/vrc_model.h,
// gl/vrc_renderer.h). Any render.transparency other than "opaque" composites front to back along
// each ray (the technique needs no fragment sorting, so the rasterized modes' names do not apply).
struct VrcSpec {
    int resolution = 128;            // voxels along the longest axis of the data
    int quantization = 32;           // bins per voxel face edge; 0 = exact float end points
    bool neighbors = false;          // also test the 26 neighbouring voxels' pieces
    float opacityThreshold = 0.99f;  // early ray termination
    // Transparent: a tube hit's alpha is 1 - (1 - alpha)^(L / 2r), L the ray's chord through the
    // hit piece's rounded cone, r the mean of its two radii (style alpha on a ray through the axis).
    bool pathLengthOpacity = false;
    bool shadows = false;  // shadows toward the light (shadowMode)
    // soft: a cone toward the light through the density; hard: a ray against the representative
    // lines of LoD level shadowLevel (core/vrc_representative.h).
    // density_cone: Kanzler et al. 2019, Sec. 5.2's soft shadows, a cone of one voxel's aperture
    // through the Eq. 1 pyramid; hard_tubes: a ray against the tubes of the voxel model's pieces
    // (shaders/vrc_lighting.glsl).
    enum class ShadowMode { Soft, Hard, DensityCone, HardTubes } shadowMode = ShadowMode::Soft;
    float shadowApertureDeg = 10;  // full apex angle of the soft shadow cone
    int shadowLevel = 1;           // hard: LoD level of the representative lines (voxels of 2^level)
    // render.vrc.ao: how AO (render.ao.enabled) is computed. cone_traced: the cones of
    // gl/ambient_occlusion.h; density_rays: Kanzler et al. 2019, Sec. 5.3, `rays` hemisphere rays
    // sampling the Eq. 1 density up to radiusVoxels; precomputed: the same over the whole sphere
    // (`sphereRays` rays) per voxel, once per model, interpolated per hit (shaders/vrc_lighting.glsl).
    struct Ao {
        enum class Method { ConeTraced, DensityRays, Precomputed } method = Method::ConeTraced;
        int rays = 16;
        int sphereRays = 100;
        float radiusVoxels = 15;
    } ao;
    // Where the voxel model is built: Auto = the GPU build on a hardware GL, the CPU build on a
    // software rasterizer (where it was measured faster; docs/performance.md).
    enum class Build { Auto, Cpu, Gpu } build = Build::Auto;
    // render.vrc.encoding: compact16 = 16 bytes per piece and an 8-byte voxel header
    // (core/vrc_model.h); paper = the packed encoding of Kanzler et al. 2019, Sec. 3.2 / Table I
    // (core/vrc_packed.h), 4-7 bytes per piece and 5 per voxel, falling back to compact16 where a
    // model does not fit it (run.json `encoding_fallback`).
    enum class Encoding { Compact16, Paper } encoding = Encoding::Compact16;
    // render.vrc.lod: rays leave the exact tubes for the LoD volume (core/vrc_model.h) where a
    // voxel of some level covers at most pixelFootprint pixels, or (transparent) once the
    // accumulated opacity reaches opacityStart, sampling ever coarser levels as it grows (the
    // paper's opacity acceleration, Sec. 5.1).
    struct Lod {
        bool enabled = false;
        float pixelFootprint = 1.0f;  // pixels per level voxel; 0 = no switch by footprint
        float opacityStart = 0.5f;    // accumulated opacity; 1 = no opacity acceleration
    } lod;
};

// The defaults here are what code that builds a Scene gets (tests, benchmarks); a scene file's
// defaults are "auto" for both technique and transparency (parseScene), resolved by the frame loop.
struct RenderSpec {
    RenderTechnique technique = RenderTechnique::Rasterized;
    Transparency transparency = Transparency::Opaque;
    BillboardPath billboards = BillboardPath::Compute;
    BillboardShape billboardShape = BillboardShape::Gross2020;  // render.billboard_shape (core/billboard.h)
    int kbufferK = 8;                                           // render.kbuffer.k, 1..16
    bool capClipping = true;                                    // render.cap_clipping (Groß & Gumhold 2020, Sect. 5.4)
    int maxPeelLayers = 0;               // render.depth_peeling.max_layers; 0 = until a pass produces nothing
    int memoryBudgetMb = 4096;           // render.memory_budget_mb: per-pixel buffers must fit
    bool referenceDepthPeeling = false;  // render.reference: "depth_peeling" -> quality.csv
    bool referenceRaytraced = false;     // render.reference: "raytraced" (exact) -> quality.csv
    float raytracedAlphaCutoff = 0.99f;  // render.raytraced.alpha_cutoff; 1 = exact compositing
    // render.raytraced.surface: the opaque visible surface as Embree's curve intersector finds it
    // (false) or recomputed by the CPU reference's rule, bit for bit (true; rt/raytraced_renderer.h).
    bool raytracedExactSurface = false;
    AoSpec ao;
    CullingSpec culling;
    OpacityOptimizationSpec opacity;
    SpheresSpec spheres;
    VrcSpec vrc;
};

// Blinn-Phong. direction is in camera space and points from the surface toward the light.
struct LightingSpec {
    glm::vec3 direction{0.3f, 0.5f, 1.0f};
    float ambient = 0.25f;
    float diffuse = 0.75f;
    float specular = 0.3f;
    float shininess = 32.0f;
};

// output.video: an H.264 MP4 of the PNG frames through ffmpeg after a complete run (cli/encode.h).
struct VideoSpec {
    std::string file;  // in output.dir unless absolute
    int fps = 30;
    int crf = 18;  // x264's constant rate factor: 0 lossless .. 51; 18 is visually lossless
};

struct OutputSpec {
    std::string dir = "out";
    std::string name = "frame.####";
    bool png = true;
    bool exr = true;
    bool aovDepth = true;
    bool aovNormal = true;
    bool aovId = false;
    bool aovAo = false;
    bool timings = true;
    std::optional<VideoSpec> video;
    // The first-surface AOVs asked for: what a technique computes and a frame keeps.
    KeptAovs keptAovs() const { return {aovDepth, aovNormal, aovId}; }
};

struct Scene {
    std::string file;  // where it was read from ("" for built-in), for messages and relative paths
    DatasetSpec dataset;
    StyleSpec style;
    CameraSpec camera;
    AnimationSpec animation;
    ImageSpec image;
    RenderSpec render;
    LightingSpec lighting;
    OutputSpec output;
    OverlaySpec overlay;
    nlohmann::json resolved;  // the JSON after --set overrides and defaults, for run.json

    int frameCount() const;
};

// Parses and validates a scene. `file` names the source in error messages (and resolves
// relative dataset paths); `overrides` are --set "key.path=value" strings applied before
// validation. Throws InputError naming the file, key path and what was expected.
Scene parseScene(const nlohmann::json& doc, const std::string& file, const std::vector<std::string>& overrides = {});
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides = {});

// Output file name for a frame: a run of '#' or "{frame:04}" becomes the zero-padded number.
std::string frameFileName(const std::string& pattern, int frame);
bool hasFrameToken(const std::string& pattern);

}  // namespace tc
