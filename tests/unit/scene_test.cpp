// Scene spec v1 (core/scene.h): defaults, every validation error with its text and location,
// --set overrides, relative paths, file loading and frame file names.
#include "core/scene.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"

namespace tc {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const json kMinimal = json::parse(R"({"dataset": {"generate": "tornado"}})");

// kMinimal with `patch` merged in (RFC 7386: null removes a key).
json with(const json& patch) {
    json doc = kMinimal;
    doc.merge_patch(patch);
    return doc;
}
json with(const char* patch) {
    return with(json::parse(patch));
}

// The InputError message parseScene throws, or a marker that makes the comparison fail readably.
std::string errorOf(const json& doc, const std::vector<std::string>& overrides = {}) {
    try {
        parseScene(doc, "scene.json", overrides);
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

fs::path tempDir(const std::string& name) {
    fs::path dir = fs::path(TUBECAST_TEST_TMP) / "scene_test" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

void writeFile(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

// ---- defaults --------------------------------------------------------------------------------

TEST(Scene, MinimalSceneParsesWithTheDocumentedDefaults) {
    Scene s = parseScene(kMinimal, "scene.json");
    EXPECT_EQ(s.file, "scene.json");
    EXPECT_EQ(s.dataset.generate, "tornado");
    EXPECT_EQ(s.dataset.path, "");
    EXPECT_EQ(s.dataset.lines, 200);
    EXPECT_EQ(s.dataset.points, 100);
    EXPECT_EQ(s.dataset.seed, 1u);

    EXPECT_FLOAT_EQ(s.style.radius.constant, 0.01f);
    EXPECT_TRUE(s.style.radius.attribute.empty());
    EXPECT_EQ(s.style.color.constant, glm::vec3(0.85f, 0.55f, 0.25f));
    EXPECT_TRUE(s.style.color.attribute.empty());
    EXPECT_FLOAT_EQ(s.style.opacity.constant, 1.0f);
    EXPECT_TRUE(s.style.opacity.attribute.empty());

    // No camera object: fit to the data from the default direction (+z).
    EXPECT_TRUE(s.camera.fit);
    EXPECT_EQ(s.camera.camera.eye, glm::vec3(0, 0, 3));
    EXPECT_EQ(s.camera.camera.target, glm::vec3(0));
    EXPECT_EQ(s.camera.camera.up, glm::vec3(0, 1, 0));
    EXPECT_FLOAT_EQ(s.camera.camera.fovYDeg, 35.0f);
    EXPECT_EQ(s.camera.camera.projection, Projection::Perspective);
    EXPECT_FLOAT_EQ(s.camera.camera.orthoHeight, 2.0f);

    EXPECT_EQ(s.animation.type, AnimationSpec::Type::None);
    EXPECT_EQ(s.frameCount(), 1);

    EXPECT_EQ(s.image.width, 640);
    EXPECT_EQ(s.image.height, 480);
    EXPECT_EQ(s.image.background, glm::vec4(0));

    // Both resolved per run: the technique by the GL at hand, the transparency by the opacities.
    EXPECT_EQ(s.render.technique, RenderTechnique::Auto);
    EXPECT_EQ(s.render.transparency, Transparency::Auto);

    EXPECT_EQ(s.lighting.direction, glm::vec3(0.3f, 0.5f, 1.0f));
    EXPECT_FLOAT_EQ(s.lighting.ambient, 0.25f);
    EXPECT_FLOAT_EQ(s.lighting.diffuse, 0.75f);
    EXPECT_FLOAT_EQ(s.lighting.specular, 0.3f);
    EXPECT_FLOAT_EQ(s.lighting.shininess, 32.0f);

    EXPECT_EQ(s.output.dir, "out");
    EXPECT_EQ(s.output.name, "frame.####");
    EXPECT_TRUE(s.output.png);
    EXPECT_TRUE(s.output.exr);
    EXPECT_TRUE(s.output.aovDepth);
    EXPECT_TRUE(s.output.aovNormal);
    EXPECT_FALSE(s.output.aovId);
    EXPECT_TRUE(s.output.timings);
    EXPECT_EQ(s.resolved, kMinimal);
}

TEST(Scene, CameraObjectWithoutFitDoesNotFit) {
    Scene s = parseScene(with(R"({"camera": {"eye": [1, 2, 3]}})"), "scene.json");
    EXPECT_FALSE(s.camera.fit);
    EXPECT_EQ(s.camera.camera.eye, glm::vec3(1, 2, 3));
}

TEST(Scene, EveryKeyOfAFullSceneIsRead) {
    json doc = json::parse(R"({
        "$schema": "x", "description": "all keys",
        "dataset": {"generate": "tornado", "lines": 10, "points": 20, "seed": 7},
        "style": {
            "radius": {"attribute": "speed", "range": [0, 2], "radius_range": [0.001, 0.002]},
            "color": {"attribute": "height", "colormap": "magma", "range": "auto"},
            "opacity": {"attribute": "speed", "range": [0.5, 1], "points": [[0, 0.1], [0.5, 0.2], [1, 0.9]]}
        },
        "camera": {"eye": [0, 0, 5], "target": [0, 1, 0], "up": [0, 0, 1], "fov_deg": 20,
                   "projection": "orthographic", "ortho_height": 3, "fit": true},
        "animation": {"type": "orbit", "frames": 12, "axis": [0, 0, 1], "degrees": 90},
        "image": {"width": 32, "height": 16, "background": [1, 1, 1]},
        "render": {"technique": "rasterized", "transparency": "opaque"},
        "lighting": {"direction": [0, 0, 1], "ambient": 0.1, "diffuse": 0.8, "specular": 0, "shininess": 8},
        "output": {"dir": "renders", "name": "f_{frame:05}", "formats": ["exr"], "aovs": ["id"], "timings": false}
    })");
    Scene s = parseScene(doc, "scene.json");
    EXPECT_EQ(s.dataset.lines, 10);
    EXPECT_EQ(s.dataset.points, 20);
    EXPECT_EQ(s.dataset.seed, 7u);
    EXPECT_EQ(s.style.radius.attribute, "speed");
    EXPECT_FALSE(s.style.radius.range.automatic);
    EXPECT_FLOAT_EQ(s.style.radius.range.hi, 2.0f);
    EXPECT_FLOAT_EQ(s.style.radius.radiusLo, 0.001f);
    EXPECT_FLOAT_EQ(s.style.radius.radiusHi, 0.002f);
    EXPECT_EQ(s.style.color.attribute, "height");
    EXPECT_EQ(s.style.color.colormap, "magma");
    EXPECT_TRUE(s.style.color.range.automatic);
    EXPECT_EQ(s.style.opacity.points.size(), 3u);
    EXPECT_FLOAT_EQ(s.style.opacity.range.lo, 0.5f);
    EXPECT_EQ(s.camera.camera.projection, Projection::Orthographic);
    EXPECT_FLOAT_EQ(s.camera.camera.orthoHeight, 3.0f);
    EXPECT_TRUE(s.camera.fit);
    EXPECT_EQ(s.animation.type, AnimationSpec::Type::Orbit);
    EXPECT_EQ(s.frameCount(), 12);
    EXPECT_FLOAT_EQ(s.animation.degrees, 90.0f);
    EXPECT_EQ(s.image.background, glm::vec4(1, 1, 1, 1));  // 3 components: alpha 1
    EXPECT_FLOAT_EQ(s.lighting.shininess, 8.0f);
    EXPECT_EQ(s.output.dir, "renders");
    EXPECT_FALSE(s.output.png);
    EXPECT_TRUE(s.output.exr);
    EXPECT_FALSE(s.output.aovDepth);
    EXPECT_FALSE(s.output.aovNormal);
    EXPECT_TRUE(s.output.aovId);
    EXPECT_FALSE(s.output.timings);
}

TEST(Scene, KeyframesAreParsedAndTheFrameCountIsTheLastKeyPlusOne) {
    Scene s = parseScene(with(R"({"animation": {"type": "keyframes", "keys": [
        {"frame": 0, "eye": [0, 0, 3]},
        {"frame": 10, "eye": [3, 0, 0], "target": [0, 1, 0], "up": [0, 0, 1]}]},
        "output": {"name": "k.###"}})"),
                         "scene.json");
    ASSERT_EQ(s.animation.keys.size(), 2u);
    EXPECT_EQ(s.animation.keys[0].target, glm::vec3(0));  // default target and up
    EXPECT_EQ(s.animation.keys[0].up, glm::vec3(0, 1, 0));
    EXPECT_EQ(s.animation.keys[1].frame, 10);
    EXPECT_EQ(s.animation.keys[1].up, glm::vec3(0, 0, 1));
    EXPECT_EQ(s.frameCount(), 11);
}

// ---- dataset ---------------------------------------------------------------------------------

TEST(Scene, RaytracedSurfaceIsEmbreeByDefaultAndExactOnRequest) {
    EXPECT_FALSE(parseScene(kMinimal, "scene.json").render.raytracedExactSurface);
    EXPECT_TRUE(parseScene(with(R"({"render": {"raytraced": {"surface": "exact"}}})"), "scene.json")
                    .render.raytracedExactSurface);
    EXPECT_NE(errorOf(with(R"({"render": {"raytraced": {"surface": "precise"}}})")).find("render.raytraced.surface"),
              std::string::npos);
}

TEST(Scene, MissingDatasetIsAnError) {
    EXPECT_EQ(errorOf(json::object()),
              "scene.json: dataset: missing required key (\"path\" to a file or \"generate\": \"tornado\")");
}

TEST(Scene, DatasetWithNeitherPathNorGenerateIsAnError) {
    EXPECT_EQ(errorOf(json::parse(R"({"dataset": {}})")),
              "scene.json: dataset.generate: missing: give \"path\" (a file) or \"generate\" (\"tornado\")");
}

TEST(Scene, DatasetWithBothPathAndGenerateIsAnError) {
    EXPECT_EQ(errorOf(json::parse(R"({"dataset": {"path": "a.vtk", "generate": "tornado"}})")),
              "scene.json: dataset.path: give either \"path\" or \"generate\", not both");
}

TEST(Scene, UnknownGeneratorListsTheValidOnes) {
    EXPECT_EQ(errorOf(json::parse(R"({"dataset": {"generate": "hurricane"}})")),
              "scene.json: dataset.generate: expected one of \"tornado\", \"propeller\", \"brain\", \"convection\", "
              "\"turbulence\", \"spiral\", \"droplets\", got \"hurricane\"");
}

TEST(Scene, GeneratorParametersAreCheckedAndLimited) {
    EXPECT_EQ(errorOf(with(R"({"dataset": {"points": 1}})")),
              "scene.json: dataset.points: expected integer 2..10000000, got 1");
    EXPECT_EQ(errorOf(with(R"({"dataset": {"seed": -1}})")),
              "scene.json: dataset.seed: expected integer 0..2147483647, got -1");
    EXPECT_EQ(errorOf(with(R"({"dataset": {"lines": 100000, "points": 10000}})")),
              "scene.json: dataset.points: lines x points = 1000000000.000000 exceeds the generator limit of 2e8 "
              "vertices");
}

TEST(Scene, GeneratorParametersWithAPathAreUnknownKeys) {
    EXPECT_EQ(errorOf(json::parse(R"({"dataset": {"path": "/data/a.vtk", "lines": 3}})")),
              "scene.json: dataset.lines: unknown key (known keys: \"frame\", \"generate\", \"path\", \"trace\")");
}

TEST(Scene, EmptyDatasetPathIsAnError) {
    EXPECT_EQ(errorOf(json::parse(R"({"dataset": {"path": ""}})")),
              "scene.json: dataset.path: expected a non-empty file path");
}

TEST(Scene, RelativeDatasetPathIsResolvedAgainstTheSceneFilesDirectory) {
    json doc = json::parse(R"({"dataset": {"path": "../data/lines.vtp"}})");
    EXPECT_EQ(parseScene(doc, "/scenes/a/scene.json").dataset.path, "/scenes/data/lines.vtp");
    EXPECT_EQ(parseScene(doc, "scenes/scene.json").dataset.path, "data/lines.vtp");
    // Absolute paths stay; a built-in scene (no file) keeps the path as given.
    EXPECT_EQ(parseScene(json::parse(R"({"dataset": {"path": "/abs/x.vtk"}})"), "/scenes/s.json").dataset.path,
              "/abs/x.vtk");
    EXPECT_EQ(parseScene(doc, "").dataset.path, "../data/lines.vtp");
}

TEST(Scene, DatasetPathFromSetIsRelativeToTheWorkingDirectory) {
    json doc = json::parse(R"({"dataset": {"path": "in_scene_dir.vtk"}})");
    EXPECT_EQ(parseScene(doc, "/scenes/scene.json", {"dataset.path=mine.vtk"}).dataset.path, "mine.vtk");
    EXPECT_EQ(parseScene(doc, "/scenes/scene.json", {R"(dataset={"path": "mine.vtk"})"}).dataset.path, "mine.vtk");
}

// ---- types and ranges ------------------------------------------------------------------------

TEST(Scene, StringWhereANumberIsExpectedIsAnError) {
    EXPECT_EQ(errorOf(with(R"({"image": {"width": "640"}})")),
              "scene.json: image.width: expected integer 1..65536, got \"640\"");
    EXPECT_EQ(errorOf(with(R"({"camera": {"fov_deg": "wide"}})")),
              "scene.json: camera.fov_deg: expected a number in [1, 170], got \"wide\"");
}

TEST(Scene, FractionalIntegerIsAnErrorButAWholeFloatIsAccepted) {
    EXPECT_EQ(errorOf(with(R"({"image": {"height": 480.5}})")),
              "scene.json: image.height: expected integer 1..65536, got 480.5");
    EXPECT_EQ(parseScene(with(R"({"image": {"height": 480.0}})"), "scene.json").image.height, 480);
}

TEST(Scene, OutOfRangeValuesAreErrors) {
    EXPECT_EQ(errorOf(with(R"({"image": {"width": 0}})")), "scene.json: image.width: expected integer 1..65536, got 0");
    EXPECT_EQ(errorOf(with(R"({"camera": {"fov_deg": 0}})")),
              "scene.json: camera.fov_deg: expected a number in [1, 170], got 0");
    EXPECT_EQ(errorOf(with(R"({"style": {"opacity": 1.5}})")),
              "scene.json: style.opacity: expected a number in [0, 1], got 1.5");
    EXPECT_EQ(errorOf(with(R"({"style": {"radius": -0.1}})")),
              "scene.json: style.radius: expected a number in [1e-09, inf], got -0.1");
    EXPECT_EQ(errorOf(with(R"({"style": {"radius": 0}})")),
              "scene.json: style.radius: expected a number in [1e-09, inf], got 0");
    EXPECT_EQ(errorOf(with(R"({"camera": {"ortho_height": -2}})")),
              "scene.json: camera.ortho_height: expected a number in [1e-09, inf], got -2");
    EXPECT_EQ(errorOf(with(R"({"lighting": {"shininess": 0.5}})")),
              "scene.json: lighting.shininess: expected a number in [1, 10000], got 0.5");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "orbit", "frames": 0}})")),
              "scene.json: animation.frames: expected integer 1..1000000, got 0");
}

TEST(Scene, WrongTypesForBooleansVectorsAndObjectsAreErrors) {
    EXPECT_EQ(errorOf(with(R"({"camera": {"fit": 1}})")), "scene.json: camera.fit: expected true or false, got 1");
    EXPECT_EQ(errorOf(with(R"({"camera": {"eye": [1, 2]}})")),
              "scene.json: camera.eye: expected an array of 3 numbers, got [1,2]");
    EXPECT_EQ(errorOf(with(R"({"camera": {"up": [0, "1", 0]}})")),
              "scene.json: camera.up: expected an array of 3 numbers, got [0,\"1\",0]");
    EXPECT_EQ(errorOf(with(R"({"image": 640})")), "scene.json: image: expected an object, got 640");
    EXPECT_EQ(errorOf(with(R"({"output": {"name": 7}})")), "scene.json: output.name: expected a string, got 7");
    EXPECT_EQ(errorOf(json::parse("[1]")), "scene.json: expected a JSON object at the top level");
}

TEST(Scene, ZeroVectorsAreErrors) {
    EXPECT_EQ(errorOf(with(R"({"camera": {"up": [0, 0, 0]}})")), "scene.json: camera.up: expected a non-zero vector");
    EXPECT_EQ(errorOf(with(R"({"lighting": {"direction": [0, 0, 0]}})")),
              "scene.json: lighting.direction: expected a non-zero vector");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "orbit", "axis": [0, 0, 0]}})")),
              "scene.json: animation.axis: expected a non-zero vector");
}

// ---- unknown keys ----------------------------------------------------------------------------

TEST(Scene, UnknownTopLevelKeyIsAnErrorThatSuggestsTheClosestKey) {
    EXPECT_EQ(errorOf(with(R"({"camra": {}})")), "scene.json: camra: unknown key (did you mean \"camera\"?)");
}

TEST(Scene, UnknownNestedKeyIsAnErrorThatSuggestsTheClosestKey) {
    EXPECT_EQ(errorOf(with(R"({"camera": {"fov_degs": 40}})")),
              "scene.json: camera.fov_degs: unknown key (did you mean \"fov_deg\"?)");
    EXPECT_EQ(errorOf(with(R"({"style": {"color": {"attribute": "speed", "colourmap": "magma"}}})")),
              "scene.json: style.color.colourmap: unknown key (did you mean \"colormap\"?)");
    EXPECT_EQ(errorOf(with(R"({"output": {"format": ["png"]}})")),
              "scene.json: output.format: unknown key (did you mean \"formats\"?)");
}

TEST(Scene, UnknownKeyFarFromAnyKnownKeyListsTheKnownKeys) {
    EXPECT_EQ(errorOf(with(R"({"image": {"quality": 9}})")),
              "scene.json: image.quality: unknown key (known keys: \"background\", \"height\", \"samples\", \"tiles\", "
              "\"width\")");
}

TEST(Scene, UnknownKeyInsideAKeyframeIsAnError) {
    EXPECT_EQ(
        errorOf(with(
            R"({"animation": {"type": "keyframes", "keys": [{"frame": 0, "eye": [0, 0, 1], "trget": [0, 0, 0]}]}})")),
        "scene.json: animation.keys[0].trget: unknown key (did you mean \"target\"?)");
}

TEST(Scene, AnimationKeysWithoutTypeKeyframesAreUnknown) {
    EXPECT_EQ(errorOf(with(R"({"animation": {"frames": 10}})")),
              "scene.json: animation.frames: unknown key (known keys: \"type\")");
}

// ---- colours and enums -----------------------------------------------------------------------

TEST(Scene, BadColourArraysAreErrors) {
    const std::string expected = "expected a colour [r, g, b] or [r, g, b, a] with components in [0, 1], got ";
    EXPECT_EQ(errorOf(with(R"({"image": {"background": [1, 0]}})")),
              "scene.json: image.background: " + expected + "[1,0]");
    EXPECT_EQ(errorOf(with(R"({"image": {"background": [1, 0, 0, 0, 1]}})")),
              "scene.json: image.background: " + expected + "[1,0,0,0,1]");
    EXPECT_EQ(errorOf(with(R"({"image": {"background": [255, 0, 0]}})")),
              "scene.json: image.background: " + expected + "[255,0,0]");
    EXPECT_EQ(errorOf(with(R"({"style": {"color": "red"}})")), "scene.json: style.color: " + expected + "\"red\"");
    EXPECT_EQ(errorOf(with(R"({"style": {"color": [-0.1, 0, 0]}})")),
              "scene.json: style.color: " + expected + "[-0.1,0,0]");
}

TEST(Scene, StyleColourWithAlphaIsAnErrorPointingToOpacity) {
    // style.color is RGB; an alpha there would be silently dropped.
    EXPECT_EQ(errorOf(with(R"({"style": {"color": [1, 0, 0, 0.5]}})")),
              "scene.json: style.color: expected a colour [r, g, b] with components in [0, 1] (opacity goes in "
              "style.opacity), got [1,0,0,0.5]");
    EXPECT_EQ(parseScene(with(R"({"style": {"color": [1, 0.5, 0]}})"), "scene.json").style.color.constant,
              glm::vec3(1, 0.5f, 0));
}

TEST(Scene, BadEnumValuesListTheValidOnes) {
    EXPECT_EQ(errorOf(with(R"({"render": {"transparency": "weighted"}})")),
              "scene.json: render.transparency: expected one of \"auto\", \"opaque\", \"kbuffer\", \"depth_peeling\", "
              "\"object_order\", "
              "\"opacity_optimization\", got \"weighted\"");
    EXPECT_EQ(errorOf(with(R"({"camera": {"projection": "fisheye"}})")),
              "scene.json: camera.projection: expected one of \"perspective\", \"orthographic\", got \"fisheye\"");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "spin"}})")),
              "scene.json: animation.type: expected one of \"none\", \"orbit\", \"keyframes\", got \"spin\"");
    EXPECT_EQ(errorOf(with(R"({"style": {"color": {"attribute": "speed", "colormap": "jet"}}})")),
              "scene.json: style.color.colormap: expected one of \"cool_warm\", \"grayscale\", \"inferno\", \"magma\", "
              "\"plasma\", \"turbo\", \"viridis\" or a ParaView preset file (.json), got \"jet\"");
    EXPECT_EQ(errorOf(with(R"({"output": {"formats": ["png", "tiff"]}})")),
              "scene.json: output.formats[1]: expected an array of strings from \"png\", \"exr\", got \"tiff\"");
    EXPECT_EQ(errorOf(with(R"({"output": {"aovs": ["ao"]}})")),
              "scene.json: output.aovs: \"ao\" needs ambient occlusion: set render.ao.enabled to true");
    EXPECT_EQ(errorOf(with(R"({"output": {"formats": []}})")),
              "scene.json: output.formats: expected at least one of \"png\", \"exr\"");
}

TEST(Scene, AoCacheDefaultsToPrecomputedAndTakesNone) {
    EXPECT_EQ(parseScene(with(R"({"render": {"ao": {}}})"), "scene.json").render.ao.cache, AoSpec::Cache::Precomputed);
    EXPECT_EQ(parseScene(with(R"({"render": {"ao": {"cache": "none"}}})"), "scene.json").render.ao.cache,
              AoSpec::Cache::None);
    EXPECT_EQ(errorOf(with(R"({"render": {"ao": {"cache": "vertex"}}})")),
              "scene.json: render.ao.cache: expected one of \"precomputed\", \"none\", got \"vertex\"");
}

TEST(Scene, BillboardShapeDefaultsToTheGross2020QuadAndTakesRectangle) {
    EXPECT_EQ(parseScene(kMinimal, "scene.json").render.billboardShape, BillboardShape::Gross2020);
    EXPECT_EQ(parseScene(kMinimal, "scene.json", {"render.billboard_shape=rectangle"}).render.billboardShape,
              BillboardShape::Rectangle);
    EXPECT_EQ(errorOf(with(R"({"render": {"billboard_shape": "box"}})")),
              "scene.json: render.billboard_shape: expected one of \"gross2020\", \"rectangle\", got \"box\"");
}

TEST(Scene, Gross2020PresetSetsThePapersConfigurationAndExplicitKeysWin) {
    // Without the preset: k = 8, no culling, cached AO.
    Scene plain = parseScene(with(R"({"render": {"ao": {}}})"), "scene.json");
    EXPECT_EQ(plain.render.kbufferK, 8);
    EXPECT_FALSE(plain.render.culling.enabled);
    EXPECT_EQ(plain.render.ao.cache, AoSpec::Cache::Precomputed);

    // Groß & Gumhold 2020, Sect. 6: k = 4, culling, AO cone traced per fragment.
    Scene paper = parseScene(with(R"({"render": {"preset": "gross2020", "ao": {}}})"), "scene.json");
    EXPECT_EQ(paper.render.kbufferK, 4);
    EXPECT_TRUE(paper.render.culling.enabled);
    EXPECT_EQ(paper.render.culling.slices, 10);
    EXPECT_EQ(paper.render.ao.cache, AoSpec::Cache::None);
    EXPECT_TRUE(paper.render.ao.enabled);  // the ao block enables AO, the preset does not
    EXPECT_FALSE(parseScene(with(R"({"render": {"preset": "gross2020"}})"), "scene.json").render.ao.enabled);

    // Keys given in the file or with --set override the preset, in either order of keys.
    Scene file = parseScene(with(R"({"render": {"kbuffer": {"k": 16}, "preset": "gross2020",
                                                "culling": {"enabled": false}, "ao": {"cache": "precomputed"}}})"),
                            "scene.json");
    EXPECT_EQ(file.render.kbufferK, 16);
    EXPECT_FALSE(file.render.culling.enabled);
    EXPECT_EQ(file.render.ao.cache, AoSpec::Cache::Precomputed);
    Scene set = parseScene(kMinimal, "scene.json",
                           {"render.preset=gross2020", "render.kbuffer.k=2", "render.culling.enabled=false"});
    EXPECT_EQ(set.render.kbufferK, 2);
    EXPECT_FALSE(set.render.culling.enabled);
    EXPECT_EQ(set.render.ao.cache, AoSpec::Cache::None);
    Scene slices = parseScene(kMinimal, "scene.json", {"render.preset=gross2020", "render.culling.slices=4"});
    EXPECT_TRUE(slices.render.culling.enabled);
    EXPECT_EQ(slices.render.culling.slices, 4);

    EXPECT_EQ(errorOf(kMinimal, {"render.preset=gross"}),
              "--set render.preset: expected one of \"none\", \"gross2020\", got \"gross\"");
    EXPECT_EQ(parseScene(with(R"({"render": {"preset": "none"}})"), "scene.json").render.kbufferK, 8);
}

// ---- attribute mappings ----------------------------------------------------------------------

TEST(Scene, AttributeMappingsRequireTheAttribute) {
    EXPECT_EQ(errorOf(with(R"({"style": {"radius": {"range": "auto"}}})")),
              "scene.json: style.radius.attribute: missing: the point attribute to map to the radius");
    EXPECT_EQ(errorOf(with(R"({"style": {"color": {"colormap": "magma"}}})")),
              "scene.json: style.color.attribute: missing: the point attribute to colour by");
    EXPECT_EQ(errorOf(with(R"({"style": {"opacity": {"attribute": ""}}})")),
              "scene.json: style.opacity.attribute: missing: the point attribute to map to opacity");
}

TEST(Scene, BadRangesAndRadiusRangesAreErrors) {
    EXPECT_EQ(errorOf(with(R"({"style": {"color": {"attribute": "speed", "range": [1, 0]}}})")),
              "scene.json: style.color.range: expected \"auto\", [min, max] with min < max or {\"percentiles\": [p_lo, "
              "p_hi]}, "
              "got [1,0]");
    EXPECT_EQ(errorOf(with(R"({"style": {"radius": {"attribute": "speed", "range": "automatic"}}})")),
              "scene.json: style.radius.range: expected \"auto\", [min, max] with min < max or {\"percentiles\": "
              "[p_lo, p_hi]}, "
              "got \"automatic\"");
    EXPECT_EQ(
        errorOf(with(R"({"style": {"radius": {"attribute": "speed", "range": {"percentiles": [5, 101]}}}})")),
        "scene.json: style.radius.range: percentiles: expected [p_lo, p_hi] with 0 <= p_lo < p_hi <= 100, got [5,101]");
    RangeSpec p = parseScene(with(R"({"style": {"color": {"attribute": "speed", "range": {"percentiles": [2, 98]}}}})"),
                             "scene.json")
                      .style.color.range;
    EXPECT_TRUE(p.percentiles);
    EXPECT_EQ(p.percentileLo, 2.0f);
    EXPECT_EQ(p.percentileHi, 98.0f);
    EXPECT_EQ(errorOf(with(R"({"style": {"radius": {"attribute": "speed", "radius_range": [0, 0.1]}}})")),
              "scene.json: style.radius.radius_range: expected [r_min, r_max] with positive radii, got [0,0.1]");
}

TEST(Scene, BadOpacityTransferFunctionPointsAreErrors) {
    const std::string prefix =
        "scene.json: style.opacity.points: expected [[t, opacity], ...] with at least 2 points, t ascending in "
        "[0, 1], opacity in [0, 1], got ";
    auto points = [](const char* p) {
        return with(json::parse(std::string(R"({"style": {"opacity": {"attribute": "speed", "points": )") + p + "}}}"));
    };
    EXPECT_EQ(errorOf(points("[[0, 1]]")), prefix + "[[0,1]]");  // one point
    // A bad element is named by its index.
    EXPECT_EQ(errorOf(points("[[0.5, 1], [0.2, 0]]")),
              "scene.json: style.opacity.points[1]: t must not decrease: 0.2 after 0.5");
    EXPECT_EQ(errorOf(points("[[0, 1], [1.5, 0]]")),
              "scene.json: style.opacity.points[1]: t must be in [0, 1], got 1.5");
    EXPECT_EQ(errorOf(points("[[0, 1], [1, 2]]")),
              "scene.json: style.opacity.points[1]: opacity must be in [0, 1], got 2");
    EXPECT_EQ(errorOf(points("[[0, 1], [1]]")), "scene.json: style.opacity.points[1]: expected [t, opacity], got [1]");
    EXPECT_EQ(errorOf(points("[[0, 1], \"x\"]")),
              "scene.json: style.opacity.points[1]: expected [t, opacity], got \"x\"");
    EXPECT_EQ(errorOf(points("\"preset\"")),
              "scene.json: style.opacity.points: expected [[t, opacity], ...] or \"colormap\" (the preset's opacity "
              "points), got \"preset\"");
    // Equal t makes a step.
    Scene s = parseScene(points("[[0, 0], [0.5, 0], [0.5, 1], [1, 1]]"), "scene.json");
    EXPECT_EQ(s.style.opacity.points.size(), 4u);
}

// ---- camera ----------------------------------------------------------------------------------

TEST(Scene, EyeEqualToTargetIsAnError) {
    EXPECT_EQ(errorOf(with(R"({"camera": {"eye": [1, 2, 3], "target": [1, 2, 3]}})")),
              "scene.json: camera.eye: eye and target coincide");
}

TEST(Scene, UpParallelToTheViewDirectionIsAnError) {
    EXPECT_EQ(errorOf(with(R"({"camera": {"eye": [0, 5, 0], "target": [0, 0, 0], "up": [0, 1, 0]}})")),
              "scene.json: camera.up: is parallel to the viewing direction (target - eye)");
    EXPECT_EQ(errorOf(with(R"({"camera": {"eye": [0, 0, 0], "target": [0, -2, 0]}})")),
              "scene.json: camera.up: is parallel to the viewing direction (target - eye)");
}

// ---- animation -------------------------------------------------------------------------------

TEST(Scene, KeyframesMustIncrease) {
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "keyframes", "keys": [
                  {"frame": 5, "eye": [0, 0, 3]}, {"frame": 5, "eye": [0, 1, 3]}]}, "output": {"name": "f.#"}})")),
              "scene.json: animation.keys[1].frame: frames must increase: 5 after 5");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "keyframes", "keys": [
                  {"frame": 5, "eye": [0, 0, 3]}, {"frame": 2, "eye": [0, 1, 3]}]}, "output": {"name": "f.#"}})")),
              "scene.json: animation.keys[1].frame: frames must increase: 2 after 5");
}

TEST(Scene, KeyframeErrorsNameTheKey) {
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "keyframes"}})")),
              "scene.json: animation.keys: missing required key");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "keyframes", "keys": []}})")),
              "scene.json: animation.keys: expected a non-empty array of {\"frame\", \"eye\", \"target\", \"up\"}");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "keyframes", "keys": [{"eye": [0, 0, 1]}]}})")),
              "scene.json: animation.keys[0].frame: missing required key");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "keyframes", "keys": [{"frame": 0}]}})")),
              "scene.json: animation.keys[0].eye: missing required key");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "keyframes", "keys": [{"frame": 0, "eye": [0, 0, 0]}]}})")),
              "scene.json: animation.keys[0].eye: eye and target coincide");
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "keyframes", "keys": [3]}})")),
              "scene.json: animation.keys[0]: expected an object, got 3");
}

TEST(Scene, MultiFrameAnimationNeedsAFrameTokenInTheOutputName) {
    EXPECT_EQ(errorOf(with(R"({"animation": {"type": "orbit", "frames": 4}, "output": {"name": "still"}})")),
              "scene.json: output.name: \"still\" has no frame token ('####' or '{frame:04}') but the animation has 4 "
              "frames");
    // A one-frame orbit needs no token; the default name has one.
    EXPECT_NO_THROW(parseScene(with(R"({"animation": {"type": "orbit", "frames": 1}, "output": {"name": "still"}})"),
                               "scene.json"));
    EXPECT_NO_THROW(parseScene(with(R"({"animation": {"type": "orbit", "frames": 4}})"), "scene.json"));
}

TEST(Scene, OutputNameMustBeAFileName) {
    EXPECT_EQ(errorOf(with(R"({"output": {"name": "sub/frame.####"}})")),
              "scene.json: output.name: expected a file name pattern without '/', e.g. \"frame.####\"");
    EXPECT_EQ(errorOf(with(R"({"output": {"dir": ""}})")), "scene.json: output.dir: expected a non-empty directory");
}

// ---- --set overrides -------------------------------------------------------------------------

TEST(Scene, SetOverridesNumbersBoolsArraysAndStrings) {
    Scene s = parseScene(kMinimal, "scene.json",
                         {"image.width=320", "camera.fit=false", "camera.eye=[1, 2, 3]", "output.name=\"shot\"",
                          "render.technique=rasterized", "style.radius=0.5e-2"});
    EXPECT_EQ(s.image.width, 320);
    EXPECT_FALSE(s.camera.fit);
    EXPECT_EQ(s.camera.camera.eye, glm::vec3(1, 2, 3));
    EXPECT_EQ(s.output.name, "shot");  // a quoted JSON string
    EXPECT_FLOAT_EQ(s.style.radius.constant, 0.005f);
    // The resolved JSON records the overrides.
    EXPECT_EQ(s.resolved["image"]["width"], 320);
    EXPECT_EQ(s.resolved["render"]["technique"], "rasterized");  // not JSON: taken as a plain string
}

TEST(Scene, SetReplacesExistingValuesAndLaterAssignmentsWin) {
    Scene s = parseScene(with(R"({"image": {"width": 100, "height": 50}})"), "scene.json",
                         {"image.width=200", "image.width=300"});
    EXPECT_EQ(s.image.width, 300);
    EXPECT_EQ(s.image.height, 50);
}

TEST(Scene, SetCreatesNestedObjects) {
    Scene s = parseScene(kMinimal, "scene.json", {"style.color.attribute=speed", "style.color.colormap=magma"});
    EXPECT_EQ(s.style.color.attribute, "speed");
    EXPECT_EQ(s.style.color.colormap, "magma");
    EXPECT_TRUE(s.resolved["style"]["color"].is_object());
}

TEST(Scene, SetTypeErrorsNameTheKeyAsSet) {
    EXPECT_EQ(errorOf(kMinimal, {"image.width=wide"}), "--set image.width: expected integer 1..65536, got \"wide\"");
    EXPECT_EQ(errorOf(kMinimal, {"camera.eye=[1,2"}), "--set camera.eye: expected an array of 3 numbers, got \"[1,2\"");
    EXPECT_EQ(errorOf(kMinimal, {"camera.fov_degs=40"}),
              "--set camera.fov_degs: unknown key (did you mean \"fov_deg\"?)");
    EXPECT_EQ(errorOf(kMinimal, {"output.formats=[\"gif\"]"}),
              "--set output.formats[0]: expected an array of strings from \"png\", \"exr\", got \"gif\"");
    // Errors in keys the file gave still point at the file.
    EXPECT_EQ(errorOf(with(R"({"image": {"height": 0}})"), {"image.width=10"}),
              "scene.json: image.height: expected integer 1..65536, got 0");
}

TEST(Scene, SetOfAWholeObjectLocatesErrorsInsideIt) {
    EXPECT_EQ(errorOf(kMinimal, {R"(camera={"eye": [0, 0, 0]})"}), "--set camera.eye: eye and target coincide");
    EXPECT_EQ(errorOf(kMinimal, {R"(animation={"type": "keyframes", "keys": [{"frame": 0}]})"}),
              "--set animation.keys[0].eye: missing required key");
}

TEST(Scene, SetIntoANonObjectIsAnError) {
    EXPECT_EQ(errorOf(kMinimal, {"dataset.generate.x=1"}),
              "--set dataset.generate.x=1: \"dataset.generate\" is not an object, cannot set \"dataset.generate.x\"");
}

TEST(Scene, MalformedSetAssignmentsAreErrors) {
    EXPECT_EQ(errorOf(kMinimal, {"image.width"}), "--set image.width: expected key.path=value");
    EXPECT_EQ(errorOf(kMinimal, {"=3"}), "--set =3: expected key.path=value");
    EXPECT_EQ(errorOf(kMinimal, {"image..width=3"}), "--set image..width=3: empty key in \"image..width\"");
}

// ---- files -----------------------------------------------------------------------------------

TEST(Scene, LoadSceneOfAMissingFileSaysSo) {
    fs::path path = tempDir("missing") / "nope.json";
    try {
        loadScene(path.string());
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), path.string() + ": no such file");
    }
}

TEST(Scene, LoadSceneOfInvalidJsonReportsLineAndColumn) {
    fs::path path = tempDir("invalid") / "bad.json";
    writeFile(path, "{\n  \"dataset\": {\"generate\": \"tornado\"},\n  \"image\": {\"width\": ,}\n}\n");
    try {
        loadScene(path.string());
        FAIL() << "no error";
    } catch (const InputError& e) {
        std::string what = e.what();
        EXPECT_EQ(what.substr(0, what.find(": invalid JSON")), path.string() + ":3:22") << what;
        EXPECT_NE(what.find("invalid JSON: syntax error while parsing value - unexpected ','"), std::string::npos)
            << what;
    }
}

TEST(Scene, LoadSceneResolvesDatasetPathsAgainstTheFile) {
    fs::path dir = tempDir("relative");
    writeFile(dir / "scene.json", R"({"dataset": {"path": "data/lines.vtp"}})");
    Scene s = loadScene((dir / "scene.json").string(), {"image.width=64"});
    EXPECT_EQ(s.dataset.path, (dir / "data/lines.vtp").string());
    EXPECT_EQ(s.file, (dir / "scene.json").string());
    EXPECT_EQ(s.image.width, 64);
}

TEST(Scene, LoadSceneReportsValidationErrorsWithTheFileName) {
    fs::path dir = tempDir("validation");
    writeFile(dir / "scene.json", R"({"dataset": {"generate": "tornado"}, "image": {"width": 0}})");
    try {
        loadScene((dir / "scene.json").string());
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  (dir / "scene.json").string() + ": image.width: expected integer 1..65536, got 0");
    }
}

// Every shipped example scene must parse (the CLI's `validate` checks the same).
TEST(Scene, EveryConfigInTheRepositoryParses) {
    fs::path configs = fs::path(__FILE__).parent_path().parent_path().parent_path() / "configs";
    ASSERT_TRUE(fs::is_directory(configs)) << configs;
    int count = 0;
    for (const auto& entry : fs::directory_iterator(configs)) {
        if (entry.path().extension() != ".json") continue;
        ++count;
        EXPECT_NO_THROW({
            try {
                loadScene(entry.path().string());
            } catch (const Error& e) {
                ADD_FAILURE() << e.what();
                throw;
            }
        }) << entry.path();
    }
    EXPECT_GE(count, 3);
}

// The examples in docs/scene-spec.md are valid scenes.
TEST(Scene, DocumentedExamplesParse) {
    fs::path doc = fs::path(__FILE__).parent_path().parent_path().parent_path() / "docs" / "scene-spec.md";
    std::ifstream in(doc);
    ASSERT_TRUE(in) << doc;
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::string> blocks;
    for (std::size_t at = text.find("```json\n"); at != std::string::npos; at = text.find("```json\n", at)) {
        at += 8;
        blocks.push_back(text.substr(at, text.find("```", at) - at));
    }
    ASSERT_EQ(blocks.size(), 2u);
    json full = json::parse(blocks[0]);
    Scene s = parseScene(full, "scene-spec.md");
    EXPECT_EQ(s.frameCount(), 36);
    // The second block is an "animation" member to put into the first.
    full["animation"] = json::parse("{" + blocks[1] + "}")["animation"];
    s = parseScene(full, "scene-spec.md");
    EXPECT_EQ(s.animation.type, AnimationSpec::Type::Keyframes);
    EXPECT_EQ(s.frameCount(), 91);
}

TEST(Scene, DemoConfigIsTheDocumentedBuiltInDemo) {
    fs::path demo = fs::path(__FILE__).parent_path().parent_path().parent_path() / "configs" / "demo.json";
    Scene s = loadScene(demo.string());
    EXPECT_EQ(s.dataset.generate, "tornado");
    EXPECT_EQ(s.dataset.lines, 400);
    EXPECT_EQ(s.dataset.points, 200);
    EXPECT_EQ(s.dataset.seed, 1u);
    EXPECT_EQ(s.style.color.attribute, "speed");
    EXPECT_EQ(s.style.color.colormap, "viridis");
    EXPECT_TRUE(s.camera.fit);
    EXPECT_EQ(s.image.width, 640);
    EXPECT_EQ(s.image.height, 480);
    EXPECT_EQ(s.frameCount(), 1);
    EXPECT_EQ(s.output.dir, "out");
    EXPECT_EQ(frameFileName(s.output.name, 0), "demo");
    EXPECT_TRUE(s.output.png && s.output.exr);
    EXPECT_TRUE(s.output.aovDepth && s.output.aovNormal && s.output.aovId);
}

// ---- frame file names ------------------------------------------------------------------------

TEST(Scene, FrameFileNameReplacesARunOfHashes) {
    EXPECT_EQ(frameFileName("frame.####", 7), "frame.0007");
    EXPECT_EQ(frameFileName("frame.####", 0), "frame.0000");
    EXPECT_EQ(frameFileName("f#_x", 42), "f42_x");  // the number is never truncated
    EXPECT_EQ(frameFileName("a.##.b", 12345), "a.12345.b");
}

TEST(Scene, FrameFileNameReplacesBraceTokens) {
    EXPECT_EQ(frameFileName("shot_{frame:04}", 7), "shot_0007");
    EXPECT_EQ(frameFileName("shot_{frame:4}", 7), "shot_0007");
    EXPECT_EQ(frameFileName("{frame}_shot", 7), "7_shot");
    EXPECT_EQ(frameFileName("{frame:02}", 123), "123");
}

TEST(Scene, FrameFileNameWithoutATokenIsUnchanged) {
    EXPECT_EQ(frameFileName("still", 3), "still");
}

TEST(Scene, HasFrameTokenRecognisesExactlyTheTokensFrameFileNameReplaces) {
    EXPECT_TRUE(hasFrameToken("frame.####"));
    EXPECT_TRUE(hasFrameToken("#"));
    EXPECT_TRUE(hasFrameToken("x{frame:04}"));
    EXPECT_TRUE(hasFrameToken("{frame}"));
    EXPECT_FALSE(hasFrameToken("still"));
    EXPECT_FALSE(hasFrameToken("frame"));
    EXPECT_FALSE(hasFrameToken("{frame:x}"));  // would be left as is: every frame would get the same name
}

}  // namespace
}  // namespace tc
