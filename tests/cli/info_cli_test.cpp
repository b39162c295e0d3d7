// `tubecast info` on datasets and scenes (cli/info.cpp), and scene-level styling keys that need
// files (ParaView presets) or VTK grids (dataset.trace), run through the binary.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "core/colormap.h"
#include "io/line_reader.h"
#include "io/paraview_preset.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

class InfoCli : public CliFixture {};

TEST_F(InfoCli, DatasetCountsBoundsAttributeRangesAndGpuBytes) {
    tc::LineSet lines;
    lines.positions = {{0, 0, 0}, {3, 4, 0}, {3, 4, 12}, {-1, 2, 5}, {-1, 2, 6}};
    lines.offsets = {0, 3, 5};
    lines.attributes = {{"temperature", {10, 20, 30, -5, 7}}};
    lines.updateBounds();
    tc::writeLineSetVtp(lines, (dir / "two.vtp").string());
    RunResult r = run("info two.vtp --json");
    ASSERT_EQ(r.code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["polylines"], 2);
    EXPECT_EQ(j["vertices"], 5);
    EXPECT_EQ(j["segments"], 3);
    EXPECT_EQ(j["bounds"]["min"], nlohmann::json({-1.0, 0.0, 0.0}));
    EXPECT_EQ(j["bounds"]["max"], nlohmann::json({3.0, 4.0, 12.0}));
    ASSERT_EQ(j["attributes"].size(), 1u);
    EXPECT_EQ(j["attributes"][0]["name"], "temperature");
    EXPECT_EQ(j["attributes"][0]["min"], -5.0);
    EXPECT_EQ(j["attributes"][0]["max"], 30.0);
    // 40 bytes per vertex (position+radius, colour, polyline id, flags), 8 per segment
    // (indices) and 32 per segment (compute billboard corners).
    EXPECT_EQ(j["gpu_buffers_bytes"]["total"], 5 * 40 + 3 * 8 + 3 * 32);
    RunResult text = run("info two.vtp");
    ASSERT_EQ(text.code, 0) << text.err;
    EXPECT_NE(text.out.find("polylines 2, vertices 5, segments 3"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("temperature"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("GPU buffers 320 bytes"), std::string::npos) << text.out;
}

TEST_F(InfoCli, SceneGetsTheDerivedAttributesItsStyleNames) {
    writeText(dir / "scene.json", R"({
  "dataset": {"generate": "tornado", "lines": 20, "points": 30, "seed": 3},
  "style": {"color": {"attribute": "curvature", "colormap": "cool_warm", "range": {"percentiles": [5, 95]}},
            "opacity": {"attribute": "local_density", "points": [[0, 0.2], [1, 1]]}}
})");
    RunResult r = run("info scene.json --json");
    ASSERT_EQ(r.code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["polylines"], 20);
    // The tornado's streamlines may end early (docs/scene-spec.md), so the count is not 20 x 30.
    const std::size_t vertices = j["vertices"], segments = j["segments"];
    EXPECT_EQ(segments, vertices - 20);
    EXPECT_EQ(j["gpu_buffers_bytes"]["total"], 40 * vertices + 40 * segments);
    std::map<std::string, nlohmann::json> byName;
    for (const auto& a : j["attributes"]) byName[a["name"].get<std::string>()] = a;
    ASSERT_TRUE(byName.count("curvature")) << r.out;
    ASSERT_TRUE(byName.count("local_density")) << r.out;
    EXPECT_TRUE(byName["curvature"]["derived"].get<bool>());
    EXPECT_GT(byName["curvature"]["max"].get<double>(), 0.0);
    EXPECT_GE(byName["local_density"]["min"].get<double>(), 1.0);  // a vertex's own line counts
    EXPECT_FALSE(byName["speed"]["derived"].get<bool>());          // the generator's own
}

TEST_F(InfoCli, TracedSceneDescribesTheStreamlines) {
    // The uniform field (1, 0, 0): straight streamlines along x.
    writeUniformVti(dir / "uniform.vti", "wind", "1 0 0");
    writeText(dir / "scene.json", R"({"dataset": {"path": "uniform.vti",
        "trace": {"vector": "wind", "seeding": "line", "seeds": 3, "line": [[0.5, 0.2, 0.5], [0.5, 0.8, 0.5]]}},
        "style": {"color": {"attribute": "arc_length"}}})");
    RunResult r = run("info scene.json --json");
    ASSERT_EQ(r.code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["polylines"], 3);
    // Each line runs across the grid in x at its seed's y, up to its last step inside the grid
    // (steps of at most 0.5 cells = 0.25 here).
    EXPECT_GE(j["bounds"]["min"][0].get<double>(), 0.0);
    EXPECT_LT(j["bounds"]["min"][0].get<double>(), 0.25);
    EXPECT_LE(j["bounds"]["max"][0].get<double>(), 1.0);
    EXPECT_GT(j["bounds"]["max"][0].get<double>(), 0.75);
    EXPECT_NEAR(j["bounds"]["min"][1].get<double>(), 0.2, 1e-5);
    EXPECT_NEAR(j["bounds"]["max"][1].get<double>(), 0.8, 1e-5);
    bool hasArc = false;
    for (const auto& a : j["attributes"])
        if (a["name"] == "arc_length") {
            hasArc = true;
            EXPECT_NEAR(a["max"].get<double>(),
                        j["bounds"]["max"][0].get<double>() - j["bounds"]["min"][0].get<double>(), 1e-4);
        }
    EXPECT_TRUE(hasArc) << r.out;

    writeText(dir / "bad.json",
              R"({"dataset": {"path": "uniform.vti", "trace": {"vector": "wind", "seeding": "line"}}})");
    RunResult bad = run("validate bad.json");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("bad.json: dataset.trace.line: missing"), std::string::npos) << bad.err;
}

TEST_F(InfoCli, PresetColormapIsResolvedRelativeToTheSceneAndValidated) {
    tc::Colormap map = tc::builtinColormap("magma");
    fs::create_directories(dir / "maps");
    tc::writeParaViewPreset(map, (dir / "maps" / "mine.json").string());
    writeText(dir / "scenes" / "scene.json", R"({"dataset": {"generate": "tornado", "lines": 4, "points": 10},
        "style": {"color": {"attribute": "height", "colormap": "../maps/mine.json", "nan_color": [1, 0, 1]}}})");
    RunResult ok = run("validate scenes/scene.json");
    EXPECT_EQ(ok.code, 0) << ok.err;
    writeText(dir / "maps" / "broken.json", "[{\"RGBPoints\": [0, 0, 0, 0, 1, 1, 1]}]");
    writeText(dir / "scenes" / "broken.json", R"({"dataset": {"generate": "tornado"},
        "style": {"color": {"attribute": "height", "colormap": "../maps/broken.json"}}})");
    RunResult bad = run("validate scenes/broken.json");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(
        bad.err.find("scenes/broken.json: style.color.colormap: maps/broken.json: RGBPoints: expected a flat array"),
        std::string::npos)
        << bad.err;
    writeText(dir / "scenes" / "jet.json", R"({"dataset": {"generate": "tornado"},
        "style": {"color": {"attribute": "height", "colormap": "jet"}}})");
    RunResult jet = run("validate scenes/jet.json");
    EXPECT_EQ(jet.code, 2);
    EXPECT_NE(jet.err.find("style.color.colormap: expected one of \"cool_warm\""), std::string::npos) << jet.err;
}

TEST_F(InfoCli, OpacityPointErrorsNameTheElement) {
    writeText(dir / "scene.json", R"({"dataset": {"generate": "tornado"},
        "style": {"opacity": {"attribute": "height", "points": [[0, 0], [0.6, 0.5], [0.4, 1]]}}})");
    RunResult r = run("validate scene.json");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("scene.json: style.opacity.points[2]: t must not decrease: 0.4 after 0.6"), std::string::npos)
        << r.err;
    writeText(dir / "range.json", R"({"dataset": {"generate": "tornado"},
        "style": {"color": {"attribute": "height", "range": {"percentiles": [50, 10]}}}})");
    RunResult range = run("validate range.json");
    EXPECT_EQ(range.code, 2);
    EXPECT_NE(range.err.find(
                  "range.json: style.color.range: percentiles: expected [p_lo, p_hi] with 0 <= p_lo < p_hi <= 100"),
              std::string::npos)
        << range.err;
}

TEST_F(InfoCli, VtkPointCloudSceneIsAParticleDataset) {
    writeText(dir / "cloud.vtk", R"(# vtk DataFile Version 3.0
cloud
ASCII
DATASET POLYDATA
POINTS 2 float
0 0 0
1 1 1
POINT_DATA 2
SCALARS radii float 1
LOOKUP_TABLE default
0.1 0.2
)");
    writeText(dir / "scene.json", R"({"dataset": {"path": "cloud.vtk"}, "render": {"technique": "spheres"}})");
    RunResult r = run("info scene.json --json");
    ASSERT_EQ(r.code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["kind"], "particles");
    EXPECT_EQ(j["particles_total"], 2);
    RunResult file = run("info cloud.vtk --json");
    ASSERT_EQ(file.code, 0) << file.err;
    EXPECT_EQ(nlohmann::json::parse(file.out)["particles_total"], 2);
}

}  // namespace
