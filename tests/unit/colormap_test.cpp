// Colormaps (core/colormap.h) against their published values, colour space interpolation against
// VTK 9.1's vtkColorTransferFunction, and ParaView preset import/export (io/paraview_preset.h).
#include "core/colormap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "core/error.h"
#include "io/paraview_preset.h"
#include "test_tmp.h"

namespace tc {
namespace {

namespace fs = std::filesystem;

// Published colours are given in 8-bit; a colormap matches when every channel is within
// `tolerance` of it (in 1/255 units).
void expectRgb8(const glm::vec3& c, int r, int g, int b, float tolerance = 0.5f) {
    EXPECT_NEAR(c.x * 255.0f, float(r), tolerance) << "red";
    EXPECT_NEAR(c.y * 255.0f, float(g), tolerance) << "green";
    EXPECT_NEAR(c.z * 255.0f, float(b), tolerance) << "blue";
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float tolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance) << "x";
    EXPECT_NEAR(a.y, b.y, tolerance) << "y";
    EXPECT_NEAR(a.z, b.z, tolerance) << "z";
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

TEST(Colormap, BuiltinsHaveTheirPublishedEndpointsAndMidpoints) {
    // matplotlib's documented hex values (viridis #440154 .. #21918c .. #fde725, and so on);
    // midpoints lie halfway between table entries 127 and 128, hence the 1-unit tolerance.
    const Colormap& viridis = builtinColormap("viridis");
    expectRgb8(viridis.sampleSrgb(0.0f), 0x44, 0x01, 0x54);
    expectRgb8(viridis.sampleSrgb(0.5f), 0x21, 0x91, 0x8c, 1.0f);
    expectRgb8(viridis.sampleSrgb(1.0f), 0xfd, 0xe7, 0x25);
    expectRgb8(builtinColormap("magma").sampleSrgb(0.0f), 0x00, 0x00, 0x04);
    expectRgb8(builtinColormap("magma").sampleSrgb(1.0f), 0xfc, 0xfd, 0xbf);
    expectRgb8(builtinColormap("inferno").sampleSrgb(0.0f), 0x00, 0x00, 0x04);
    expectRgb8(builtinColormap("inferno").sampleSrgb(1.0f), 0xfc, 0xff, 0xa4);
    expectRgb8(builtinColormap("plasma").sampleSrgb(0.0f), 0x0d, 0x08, 0x87);
    expectRgb8(builtinColormap("plasma").sampleSrgb(1.0f), 0xf0, 0xf9, 0x21);
    // Turbo: Google's table starts at (0.18995, 0.07176, 0.23217), ends at (0.4796, 0.01583, 0.01055).
    expectNear(builtinColormap("turbo").sampleSrgb(0.0f), {0.18995f, 0.07176f, 0.23217f}, 1e-6f);
    expectNear(builtinColormap("turbo").sampleSrgb(1.0f), {0.47960f, 0.01583f, 0.01055f}, 1e-6f);
    expectNear(builtinColormap("grayscale").sampleSrgb(0.25f), glm::vec3(0.25f), 1e-6f);
    for (const auto& name : builtinColormapNames()) {
        const Colormap& m = builtinColormap(name);
        EXPECT_NO_THROW(validateColormap(m, name)) << name;
        if (name != "cool_warm" && name != "grayscale") {
            EXPECT_EQ(m.t.size(), 256u) << name;
        }
    }
}

TEST(Colormap, TableEntriesAreHitExactlyAtTheirPositions) {
    const Colormap& plasma = builtinColormap("plasma");
    // Entry 64 of matplotlib's plasma table.
    expectNear(plasma.sampleSrgb(64.0f / 255.0f), plasma.srgb[64], 1e-6f);
    expectNear(plasma.srgb[64], {0.494877f, 0.011990f, 0.657865f}, 0);
}

TEST(Colormap, CoolWarmIsMorelandsDivergingMap) {
    const Colormap& cw = builtinColormap("cool_warm");
    EXPECT_EQ(cw.space, ColorSpace::Diverging);
    // Moreland 2009, Table 1 and his published 33-entry table (CoolWarmFloat33): endpoints
    // (59, 76, 192) and (180, 4, 38), white point (221, 221, 221), quarter points (141, 176, 254)
    // and (244, 154, 123).
    expectRgb8(cw.sampleSrgb(0.0f), 59, 76, 192, 0.01f);
    expectRgb8(cw.sampleSrgb(1.0f), 180, 4, 38, 0.01f);
    expectRgb8(cw.sampleSrgb(0.5f), 221, 221, 221, 0.6f);
    expectRgb8(cw.sampleSrgb(0.25f), 141, 176, 254, 0.6f);
    expectRgb8(cw.sampleSrgb(0.75f), 244, 154, 123, 0.6f);
    // The centre is grey: equal channels.
    glm::vec3 mid = cw.sampleSrgb(0.5f);
    EXPECT_NEAR(mid.x, mid.y, 1e-4f);
    EXPECT_NEAR(mid.y, mid.z, 1e-4f);
}

// Reference values from VTK 9.1's vtkColorTransferFunction (python3-vtk9) with nodes
// (0, 59/255, 76/255, 192/255) and (1, 180/255, 4/255, 38/255) in each colour space.
TEST(Colormap, ColourSpacesMatchVtkColorTransferFunction) {
    const glm::vec3 a = glm::vec3(59, 76, 192) / 255.0f, b = glm::vec3(180, 4, 38) / 255.0f;
    expectNear(interpolateSrgb(ColorSpace::Lab, a, b, 0.25f), {0.466813f, 0.253075f, 0.595160f}, 2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Lab, a, b, 0.5f), {0.580663f, 0.202499f, 0.443043f}, 2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Lab, a, b, 0.75f), {0.653884f, 0.138599f, 0.296020f}, 2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Diverging, a, b, 0.25f), glm::vec3(141.096f, 175.602f, 253.773f) / 255.0f,
               2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Diverging, a, b, 0.5f), glm::vec3(220.676f, 220.680f, 220.676f) / 255.0f,
               2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Diverging, a, b, 0.75f), glm::vec3(244.396f, 153.795f, 122.830f) / 255.0f,
               2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Hsv, a, b, 0.25f), {0.376427f, 0.174936f, 0.741176f}, 2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Hsv, a, b, 0.5f), {0.631629f, 0.120176f, 0.729412f}, 2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Hsv, a, b, 0.75f), {0.717647f, 0.067093f, 0.507415f}, 2e-5f);
    expectNear(interpolateSrgb(ColorSpace::Rgb, a, b, 0.25f), {0.35f, 0.227451f, 0.601961f}, 2e-6f);
    // VTK's Step: anything past a node takes the next node's colour.
    expectNear(interpolateSrgb(ColorSpace::Step, a, b, 0.0f), a, 0);
    expectNear(interpolateSrgb(ColorSpace::Step, a, b, 0.4f), b, 0);
}

TEST(Colormap, LabInterpolationDiffersFromRgbWhereItShould) {
    // Blue to yellow: the RGB midpoint is a dull grey (0.5, 0.5, 0.5) while Lab keeps the
    // lightness halfway between the ends (L* 32.3 and 97.1 -> 64.7) with a different hue.
    const glm::vec3 blue{0, 0, 1}, yellow{1, 1, 0};
    glm::vec3 rgbMid = interpolateSrgb(ColorSpace::Rgb, blue, yellow, 0.5f);
    glm::vec3 labMid = interpolateSrgb(ColorSpace::Lab, blue, yellow, 0.5f);
    expectNear(rgbMid, glm::vec3(0.5f), 1e-6f);
    EXPECT_GT(glm::length(labMid - rgbMid), 0.1f);
    EXPECT_NEAR(srgbToLab(labMid).x, 0.5f * (srgbToLab(blue).x + srgbToLab(yellow).x), 0.05f);
    EXPECT_GT(std::abs(srgbToLab(rgbMid).x - srgbToLab(labMid).x), 1.0f);
    // Grey to grey: every space agrees (no hue to bend).
    expectNear(interpolateSrgb(ColorSpace::Lab, glm::vec3(0.2f), glm::vec3(0.8f), 0.0f), glm::vec3(0.2f), 1e-5f);
}

TEST(Colormap, LabConversionRoundTripsAndHitsCieWhite) {
    expectNear(srgbToLab({1, 1, 1}), {100.0f, 0.0f, 0.0f}, 0.05f);  // D65 white
    expectNear(srgbToLab({0, 0, 0}), {0, 0, 0}, 1e-4f);
    for (float r = 0; r <= 1.0f; r += 0.25f)
        for (float g = 0; g <= 1.0f; g += 0.25f)
            for (float b = 0; b <= 1.0f; b += 0.25f) {
                // VTK's 4-digit XYZ matrices are not exact inverses of each other: a round trip is
                // good to ~3e-4, which is what ParaView does too.
                expectNear(labToSrgb(srgbToLab({r, g, b})), {r, g, b}, 5e-4f);
            }
}

TEST(Colormap, NanSamplesGiveTheNanColour) {
    Colormap m = builtinColormap("grayscale");
    expectNear(m.sampleSrgb(std::nanf("")), glm::vec3(0.5f), 0);
    m.nanColor = glm::vec3(1, 0, 1);
    expectNear(m.sampleSrgb(std::nanf("")), {1, 0, 1}, 0);
}

TEST(Colormap, UnknownNameListsTheBuiltins) {
    EXPECT_EQ(errorOf([] { builtinColormap("jet"); }),
              "unknown colormap \"jet\" (built-in: cool_warm, grayscale, inferno, magma, plasma, turbo, viridis)");
}

// --- ParaView presets --------------------------------------------------------------------

TEST(ParaViewPreset, TrailingCommasAreRemovedOutsideStringsOnly) {
    EXPECT_EQ(stripTrailingCommas(R"([1, 2, ])"), R"([1, 2  ])");
    EXPECT_EQ(stripTrailingCommas("{\"a\": [1,\n],\n}"), "{\"a\": [1 \n] \n}");
    EXPECT_EQ(stripTrailingCommas(R"(["a,]", "b\",}"])"), R"(["a,]", "b\",}"])");
    EXPECT_EQ(stripTrailingCommas(R"([1, 2])"), R"([1, 2])");
}

TEST(ParaViewPreset, ParaViewsOwnExportWithTrailingCommaIsRead) {
    // The shape of ParaView 5.x's "Export" of Cool to Warm, trailing comma included.
    fs::path d = fs::path(test::testDir());
    std::ofstream(d / "cw.json") << R"([
	{
		"ColorSpace" : "Diverging",
		"Creator" : "Pure Matplotlib",
		"DefaultMap" : true,
		"Name" : "Cool to Warm",
		"NanColor" : [1, 1, 0],
		"RGBPoints" : [
			-5, 0.23137254902, 0.298039215686, 0.752941176471,
			0, 0.865, 0.865, 0.865,
			5, 0.705882352941, 0.0156862745098, 0.149019607843,
		],
	},
]
)";
    Colormap m = readParaViewPreset((d / "cw.json").string());
    EXPECT_EQ(m.name, "Cool to Warm");
    EXPECT_EQ(m.space, ColorSpace::Diverging);
    ASSERT_EQ(m.t.size(), 3u);
    EXPECT_FLOAT_EQ(m.t[1], 0.5f);  // data positions -5..5 rescaled to 0..1
    ASSERT_TRUE(m.nanColor.has_value());
    expectNear(*m.nanColor, {1, 1, 0}, 0);
    expectRgb8(m.sampleSrgb(0.5f), 221, 221, 221, 0.6f);
    // ParaView's 3-point version and Moreland's 2-point definition agree in between.
    expectNear(m.sampleSrgb(0.25f), builtinColormap("cool_warm").sampleSrgb(0.25f), 2.0f / 255.0f);
}

TEST(ParaViewPreset, WriteThenReadGivesTheSameColormap) {
    fs::path d = fs::path(test::testDir());
    for (const auto& name : builtinColormapNames()) {
        Colormap m = builtinColormap(name);
        m.nanColor = glm::vec3(0.25f, 0.5f, 1.0f);
        m.opacity = {{0.0f, 0.1f}, {0.3f, 0.75f}, {1.0f, 1.0f}};
        std::string path = (d / (name + ".json")).string();
        writeParaViewPreset(m, path);
        Colormap back = readParaViewPreset(path);
        EXPECT_EQ(back.name, m.name);
        EXPECT_EQ(back.space, m.space) << name;
        EXPECT_EQ(back.t, m.t) << name;
        EXPECT_EQ(back.srgb, m.srgb) << name;
        EXPECT_EQ(back.nanColor, m.nanColor) << name;
        EXPECT_EQ(back.opacity, m.opacity) << name;
        for (float x : {0.1f, 0.5f, 0.9f}) EXPECT_EQ(back.sampleSrgb(x), m.sampleSrgb(x)) << name;
    }
}

TEST(ParaViewPreset, LabPresetInterpolatesInLab) {
    nlohmann::json preset = {{"Name", "lab"}, {"ColorSpace", "Lab"}, {"RGBPoints", {0, 0, 0, 1, 10, 1, 1, 0}}};
    Colormap m = colormapFromParaViewPreset(preset, "lab.json");
    expectNear(m.sampleSrgb(0.5f), interpolateSrgb(ColorSpace::Lab, {0, 0, 1}, {1, 1, 0}, 0.5f), 0);
    EXPECT_GT(glm::length(m.sampleSrgb(0.5f) - glm::vec3(0.5f)), 0.1f);
}

TEST(ParaViewPreset, OpacityPointsAreRescaledAndShaped) {
    nlohmann::json preset = {{"RGBPoints", {0, 0, 0, 0, 1, 1, 1, 1}},
                             {"Points", {10, 0.0, 0.5, 0.0, 20, 1.0, 0.5, 0.0, 30, 0.5, 0.5, 0.0}}};
    Colormap m = colormapFromParaViewPreset(preset, "p.json");
    ASSERT_EQ(m.opacity.size(), 3u);
    EXPECT_EQ(m.opacity[1], glm::vec2(0.5f, 1.0f));
    // Midpoint 0.25, sharpness 0 on the first segment: half opacity is reached a quarter of the way.
    preset["Points"] = {0, 0.0, 0.25, 0.0, 1, 1.0, 0.5, 0.0};
    m = colormapFromParaViewPreset(preset, "p.json");
    EXPECT_EQ(m.opacity.size(), 17u);
    EXPECT_NEAR(m.opacity[4].x, 0.25f, 1e-6f);
    EXPECT_NEAR(m.opacity[4].y, 0.5f, 1e-6f);
}

TEST(ParaViewPreset, MalformedPresetsNameTheKey) {
    auto err = [](const nlohmann::json& j) { return errorOf([&] { colormapFromParaViewPreset(j, "p.json"); }); };
    EXPECT_EQ(err({{"Name", "x"}}), "p.json: RGBPoints: missing: the colour control points [x, r, g, b, ...]");
    EXPECT_EQ(err({{"IndexedColors", {1, 0, 0}}}),
              "p.json: IndexedColors: categorical (indexed) presets are not supported; expected \"RGBPoints\"");
    EXPECT_EQ(err({{"RGBPoints", {0, 0, 0, 0, 1, 1, 1}}}),
              "p.json: RGBPoints: expected a flat array of 4 numbers per point and at least 2 points, got 7 values");
    EXPECT_EQ(err({{"RGBPoints", {0, 0, 0, 0, 1, 1, 2, 1}}}),
              "p.json: RGBPoints[6]: colour components must be in [0, 1], got 2.000000");
    EXPECT_EQ(err({{"RGBPoints", {1, 0, 0, 0, 0, 1, 1, 1}}}),
              "p.json: RGBPoints[4]: point positions must not decrease (0.000000 after 1.000000)");
    EXPECT_EQ(err({{"RGBPoints", {0, 0, 0, 0, 1, 1, 1, 1}}, {"ColorSpace", "CMYK"}}),
              "p.json: ColorSpace: expected \"RGB\", \"Lab\", \"Diverging\", \"HSV\" or \"Step\", got \"CMYK\"");
    EXPECT_EQ(err({{"RGBPoints", {0, 0, 0, 0, 1, 1, 1, 1}}, {"Points", {0, 0, 0.5, 0, 1, 3, 0.5, 0}}}),
              "p.json: Points[5]: opacity must be in [0, 1], got 3.000000");
}

TEST(ParaViewPreset, SyntaxErrorsGiveLineAndColumn) {
    fs::path d = fs::path(test::testDir());
    std::ofstream(d / "bad.json") << "[\n  {\"RGBPoints\": [0, 0, 0, 0 1, 1, 1, 1]}\n]\n";
    std::string e = errorOf([&] { readParaViewPreset((d / "bad.json").string()); });
    EXPECT_NE(e.find("bad.json:2:29: invalid JSON"), std::string::npos) << e;
    EXPECT_EQ(errorOf([&] { readParaViewPreset((d / "none.json").string()); }),
              (d / "none.json").string() + ": no such file");
}

TEST(ParaViewPreset, StylePresetsAreLoadedAndErrorsNameTheSceneKey) {
    fs::path d = fs::path(test::testDir());
    writeParaViewPreset(builtinColormap("magma"), (d / "m.json").string());
    StyleSpec style;
    style.color.colormap = (d / "m.json").string();
    loadStylePresets(style, "scene.json");
    ASSERT_TRUE(style.color.preset);
    EXPECT_EQ(style.color.preset->srgb, builtinColormap("magma").srgb);
    StyleSpec missing;
    missing.color.colormap = (d / "nope.json").string();
    EXPECT_EQ(errorOf([&] { loadStylePresets(missing, "scene.json"); }),
              "scene.json: style.color.colormap: " + (d / "nope.json").string() + ": no such file");
    StyleSpec builtin;
    loadStylePresets(builtin, "scene.json");  // viridis: nothing to load
    EXPECT_FALSE(builtin.color.preset);
}

}  // namespace
}  // namespace tc
