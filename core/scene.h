#pragma once
// Scene spec v1: the typed, validated form of a scene JSON file (docs/scene-spec.md).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/camera.h"

namespace tc {

struct DatasetSpec {
    std::string path;       // a file (resolved relative to the scene file), or
    std::string generate;   // a built-in generator: "tornado"
    int lines = 200;        // generator parameters
    int points = 100;
    std::uint32_t seed = 1;
};

// A value range for attribute mappings: explicit, or "auto" (the attribute's min/max).
struct RangeSpec {
    bool automatic = true;
    float lo = 0.0f, hi = 1.0f;
};

// style.radius: a constant, or an attribute mapped linearly from `range` to `radius_range`.
struct RadiusSpec {
    float constant = 0.01f;
    std::string attribute;  // empty = constant
    RangeSpec range;
    float radiusLo = 0.005f, radiusHi = 0.02f;
};

// style.color: a constant sRGB colour, or an attribute through a colormap.
struct ColorSpec {
    glm::vec3 constant{0.85f, 0.55f, 0.25f};  // sRGB
    std::string attribute;
    std::string colormap = "viridis";
    RangeSpec range;
};

// style.opacity: a constant, or an attribute through a piecewise linear transfer function over
// the normalised attribute value t in [0,1]: points [[t0, a0], [t1, a1], ...], t ascending.
struct OpacitySpec {
    float constant = 1.0f;
    std::string attribute;
    RangeSpec range;
    std::vector<glm::vec2> points{{0.0f, 0.0f}, {1.0f, 1.0f}};
};

struct StyleSpec {
    RadiusSpec radius;
    ColorSpec color;
    OpacitySpec opacity;
};

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
};

enum class RenderTechnique { Rasterized };
enum class Transparency { Opaque, ObjectOrder, KBuffer, DepthPeeling };

// Where the rasterized path builds each segment's billboard: a compute pre-pass (default), the
// vertex shader (vertex pulling, once per quad corner) or a geometry shader (the paper's layout).
enum class BillboardPath { Compute, Vertex, Geometry };

// render.ao: voxel cone traced ambient occlusion from a line density volume (Groß & Gumhold 2020,
// Sect. 5.3), shared by every technique that shades surfaces.
struct AoSpec {
    bool enabled = false;
    int resolution = 256;     // voxels along the longest axis of the data
    int cones = 3;
    float apertureDeg = 50;   // full apex angle of each cone, 10..90
    float distance = 0.25f;   // cone length as a fraction of the bounding-box diagonal
    float strength = 1;
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

struct RenderSpec {
    RenderTechnique technique = RenderTechnique::Rasterized;
    Transparency transparency = Transparency::Opaque;
    BillboardPath billboards = BillboardPath::Compute;
    int kbufferK = 8;              // render.kbuffer.k, 1..16
    bool capClipping = true;       // render.cap_clipping (Groß & Gumhold 2020, Sect. 5.4)
    int maxPeelLayers = 0;         // render.depth_peeling.max_layers; 0 = until a pass produces nothing
    int memoryBudgetMb = 4096;     // render.memory_budget_mb: per-pixel buffers must fit
    bool referenceDepthPeeling = false;  // render.reference: "depth_peeling" -> quality.csv
    AoSpec ao;
    CullingSpec culling;
};

// Blinn-Phong. direction is in camera space and points from the surface toward the light.
struct LightingSpec {
    glm::vec3 direction{0.3f, 0.5f, 1.0f};
    float ambient = 0.25f;
    float diffuse = 0.75f;
    float specular = 0.3f;
    float shininess = 32.0f;
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
    nlohmann::json resolved;  // the JSON after --set overrides and defaults, for run.json

    int frameCount() const;
};

// Parses and validates a scene. `file` names the source in error messages (and resolves
// relative dataset paths); `overrides` are --set "key.path=value" strings applied before
// validation. Throws InputError naming the file, key path and what was expected.
Scene parseScene(const nlohmann::json& doc, const std::string& file,
                 const std::vector<std::string>& overrides = {});
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides = {});

// Output file name for a frame: a run of '#' or "{frame:04}" becomes the zero-padded number.
std::string frameFileName(const std::string& pattern, int frame);
bool hasFrameToken(const std::string& pattern);

}  // namespace tc
