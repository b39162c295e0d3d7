// Styling (core/styling.h): attributes -> per-vertex radius and linear RGBA, the segment index
// buffer, flags and bounds.
#include "core/styling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/color.h"
#include "core/colormap.h"
#include "core/error.h"

namespace tc {
namespace {

// Three polylines of 3, 2 and 4 vertices along x at y = 0, 1, 2; attribute "a" = vertex index
// (0..8), "b" = 10 * vertex index.
LineSet threeLines() {
    LineSet lines;
    const int counts[] = {3, 2, 4};
    for (int p = 0; p < 3; ++p) {
        for (int k = 0; k < counts[p]; ++k) lines.positions.push_back({float(k), float(p), 0.0f});
        lines.offsets.push_back(std::uint32_t(lines.positions.size()));
    }
    Attribute a{"a", {}}, b{"b", {}};
    for (std::size_t i = 0; i < lines.positions.size(); ++i) {
        a.values.push_back(float(i));
        b.values.push_back(10.0f * float(i));
    }
    lines.attributes = {a, b};
    for (auto& attr : lines.attributes) attr.updateRange();
    lines.updateBounds();
    return lines;
}

std::string styleError(const LineSet& lines, const StyleSpec& style) {
    try {
        styleLines(lines, style, "scene.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float tolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance) << "x";
    EXPECT_NEAR(a.y, b.y, tolerance) << "y";
    EXPECT_NEAR(a.z, b.z, tolerance) << "z";
}

TEST(Styling, ConstantStyleIsTheSameForEveryVertexAndLinearised) {
    StyleSpec style;
    style.radius.constant = 0.25f;
    style.color.constant = {1.0f, 0.5f, 0.0f};
    style.opacity.constant = 0.75f;
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    ASSERT_EQ(s.vertexCount(), 9u);
    // sRGB 0.5 is linear 0.214041 (IEC 61966-2-1).
    for (std::size_t i = 0; i < s.vertexCount(); ++i) {
        EXPECT_FLOAT_EQ(s.positionRadius[i].w, 0.25f);
        EXPECT_FLOAT_EQ(s.color[i].x, 1.0f);
        EXPECT_NEAR(s.color[i].y, 0.214041f, 1e-5f);
        EXPECT_FLOAT_EQ(s.color[i].z, 0.0f);
        EXPECT_FLOAT_EQ(s.color[i].w, 0.75f);
    }
    EXPECT_FLOAT_EQ(s.maxRadius, 0.25f);
    EXPECT_EQ(glm::vec3(s.positionRadius[4]), glm::vec3(1, 1, 0));
}

TEST(Styling, SrgbConversionRoundTripsAndHitsKnownValues) {
    EXPECT_FLOAT_EQ(srgbToLinear(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgbToLinear(1.0f), 1.0f);
    EXPECT_NEAR(srgbToLinear(0.04045f), 0.04045f / 12.92f, 1e-7f);  // the linear toe
    EXPECT_NEAR(srgbToLinear(0.5f), 0.214041f, 1e-6f);
    for (float c = 0.0f; c <= 1.0f; c += 0.01f) EXPECT_NEAR(linearToSrgb(srgbToLinear(c)), c, 1e-5f);
}

TEST(Styling, RadiusIsMappedLinearlyFromAnExplicitRangeAndClamped) {
    StyleSpec style;
    style.radius.attribute = "b";
    style.radius.range = {false, 20.0f, 60.0f};
    style.radius.radiusLo = 0.1f;
    style.radius.radiusHi = 0.5f;
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    // b = 0, 10, 20 (clamped to lo), 30, 40, 50, 60, 70, 80 (clamped to hi).
    const float expected[] = {0.1f, 0.1f, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.5f, 0.5f};
    for (std::size_t i = 0; i < 9; ++i) EXPECT_NEAR(s.positionRadius[i].w, expected[i], 1e-6f) << "vertex " << i;
    EXPECT_FLOAT_EQ(s.maxRadius, 0.5f);
}

TEST(Styling, RadiusIsMappedLinearlyFromTheAutomaticRange) {
    StyleSpec style;
    style.radius.attribute = "a";  // range auto: 0..8
    style.radius.radiusLo = 1.0f;
    style.radius.radiusHi = 3.0f;
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    for (std::size_t i = 0; i < 9; ++i)
        EXPECT_NEAR(s.positionRadius[i].w, 1.0f + 2.0f * float(i) / 8.0f, 1e-6f) << "vertex " << i;
}

TEST(Styling, ConstantAttributeMapsToTheLowEnd) {
    LineSet lines = threeLines();
    for (float& v : lines.attributes[0].values) v = 4.0f;
    lines.attributes[0].updateRange();
    StyleSpec style;
    style.radius.attribute = "a";
    StyledLines s = styleLines(lines, style, "scene.json");
    for (std::size_t i = 0; i < 9; ++i) EXPECT_FLOAT_EQ(s.positionRadius[i].w, style.radius.radiusLo);
}

TEST(Styling, ColourmapEndpointsAreTheLinearisedColormapEnds) {
    StyleSpec style;
    style.color.attribute = "a";
    style.color.colormap = "viridis";
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    const Colormap& viridis = builtinColormap("viridis");
    // a = 0 -> t = 0, a = 8 -> t = 1.
    expectNear(glm::vec3(s.color[0]), srgbToLinear(viridis.srgb.front()), 1e-6f);
    expectNear(glm::vec3(s.color[8]), srgbToLinear(viridis.srgb.back()), 1e-6f);
    // The first viridis entry (0.267, 0.0049, 0.329) in linear space:
    expectNear(glm::vec3(s.color[0]), {0.05795f, 0.000377f, 0.08866f}, 2e-5f);
    // t = 0.5 (a = 4) lies halfway between viridis' table entries 127 and 128; the colormap
    // interpolates in sRGB, then the result is linearised.
    glm::vec3 mid = glm::mix(viridis.srgb[127], viridis.srgb[128], 0.5f);
    expectNear(glm::vec3(s.color[4]), srgbToLinear(mid), 1e-5f);
    for (std::size_t i = 0; i < 9; ++i) EXPECT_FLOAT_EQ(s.color[i].w, 1.0f);
}

TEST(Styling, ColourRangeClampsToTheColormapEnds) {
    StyleSpec style;
    style.color.attribute = "b";
    style.color.colormap = "grayscale";
    style.color.range = {false, 30.0f, 50.0f};
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    expectNear(glm::vec3(s.color[0]), {0, 0, 0}, 0);
    expectNear(glm::vec3(s.color[8]), {1, 1, 1}, 1e-6f);
    expectNear(glm::vec3(s.color[4]), glm::vec3(srgbToLinear(0.5f)), 1e-6f);  // b = 40: sRGB grey 0.5
}

TEST(Styling, NanAttributeValuesGetGreyAndTheLowEnd) {
    LineSet lines = threeLines();
    lines.attributes[0].values[2] = std::numeric_limits<float>::quiet_NaN();
    lines.attributes[0].updateRange();
    StyleSpec style;
    style.color.attribute = "a";
    style.radius.attribute = "a";
    StyledLines s = styleLines(lines, style, "scene.json");
    expectNear(glm::vec3(s.color[2]), glm::vec3(srgbToLinear(0.5f)), 1e-6f);
    EXPECT_FLOAT_EQ(s.positionRadius[2].w, style.radius.radiusLo);
}

TEST(Styling, OpacityFollowsTheTransferFunction) {
    StyleSpec style;
    style.opacity.attribute = "a";  // t = a / 8
    style.opacity.points = {{0.0f, 0.0f}, {0.5f, 0.2f}, {1.0f, 1.0f}};
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    EXPECT_NEAR(s.color[0].w, 0.0f, 1e-6f);
    EXPECT_NEAR(s.color[2].w, 0.1f, 1e-6f);  // t = 0.25
    EXPECT_NEAR(s.color[4].w, 0.2f, 1e-6f);  // t = 0.5
    EXPECT_NEAR(s.color[6].w, 0.6f, 1e-6f);  // t = 0.75
    EXPECT_NEAR(s.color[8].w, 1.0f, 1e-6f);
}

TEST(Styling, TransferFunctionInterpolatesLinearlyBetweenPoints) {
    const std::vector<glm::vec2> tf = {{0.2f, 0.1f}, {0.6f, 0.9f}, {0.8f, 0.5f}};
    EXPECT_FLOAT_EQ(evaluateTransferFunction(tf, 0.2f), 0.1f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(tf, 0.4f), 0.5f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(tf, 0.6f), 0.9f);
    EXPECT_NEAR(evaluateTransferFunction(tf, 0.7f), 0.7f, 1e-6f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(tf, 0.8f), 0.5f);
}

TEST(Styling, TransferFunctionIsHeldOutsideItsPoints) {
    const std::vector<glm::vec2> tf = {{0.2f, 0.1f}, {0.8f, 0.5f}};
    EXPECT_FLOAT_EQ(evaluateTransferFunction(tf, 0.0f), 0.1f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(tf, -5.0f), 0.1f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(tf, 1.0f), 0.5f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(tf, 7.0f), 0.5f);
}

TEST(Styling, TransferFunctionEdgeCases) {
    EXPECT_FLOAT_EQ(evaluateTransferFunction({}, 0.3f), 1.0f);                // no points: opaque
    EXPECT_FLOAT_EQ(evaluateTransferFunction({{0.5f, 0.25f}}, 0.0f), 0.25f);  // one point: constant
    EXPECT_FLOAT_EQ(evaluateTransferFunction({{0.5f, 0.25f}}, 1.0f), 0.25f);
    // Two points at the same t make a step; exactly at the step the lower value is taken, just
    // after it the upper one.
    const std::vector<glm::vec2> step = {{0.0f, 0.0f}, {0.5f, 0.0f}, {0.5f, 1.0f}, {1.0f, 1.0f}};
    EXPECT_FLOAT_EQ(evaluateTransferFunction(step, 0.49f), 0.0f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(step, 0.5f), 0.0f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(step, 0.51f), 1.0f);
    // Zero-width interval at the start.
    EXPECT_FLOAT_EQ(evaluateTransferFunction({{0.0f, 0.3f}, {0.0f, 0.7f}}, 0.0f), 0.3f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction({{0.0f, 0.3f}, {0.0f, 0.7f}}, 0.1f), 0.7f);
}

TEST(Styling, MissingAttributeErrorNamesTheKeyAndListsTheAvailableAttributes) {
    StyleSpec style;
    style.color.attribute = "velocity";
    EXPECT_EQ(styleError(threeLines(), style),
              "scene.json: style.color.attribute: the dataset has no attribute \"velocity\" (available: a, b; derived: "
              "arc_length, line_length, curvature, torsion, local_density, speed)");
    style = {};
    style.radius.attribute = "r";
    EXPECT_EQ(styleError(threeLines(), style),
              "scene.json: style.radius.attribute: the dataset has no attribute \"r\" (available: a, b; derived: "
              "arc_length, line_length, curvature, torsion, local_density, speed)");
    style = {};
    style.opacity.attribute = "o";
    LineSet bare = threeLines();
    bare.attributes.clear();
    EXPECT_EQ(styleError(bare, style),
              "scene.json: style.opacity.attribute: the dataset has no attribute \"o\" (available: none; derived: "
              "arc_length, line_length, curvature, torsion, local_density, speed)");
}

TEST(Styling, SegmentsJoinConsecutiveVerticesWithinPolylinesOnly) {
    LineSet lines = threeLines();
    StyledLines s = styleLines(lines, StyleSpec{}, "scene.json");
    ASSERT_EQ(s.segmentCount(), lines.segmentCount());
    EXPECT_EQ(s.segmentCount(), 6u);  // 2 + 1 + 3
    EXPECT_EQ(s.segmentVertices, (std::vector<std::uint32_t>{0, 1, 1, 2, 3, 4, 5, 6, 6, 7, 7, 8}));
    for (std::size_t seg = 0; seg < s.segmentCount(); ++seg) {
        std::uint32_t a = s.segmentVertices[2 * seg], b = s.segmentVertices[2 * seg + 1];
        EXPECT_EQ(b, a + 1) << "segment " << seg;
        EXPECT_EQ(s.polylineId[a], s.polylineId[b]) << "segment " << seg << " crosses polylines";
    }
}

TEST(Styling, PolylineIdsAndFirstLastFlags) {
    StyledLines s = styleLines(threeLines(), StyleSpec{}, "scene.json");
    EXPECT_EQ(s.polylineId, (std::vector<std::uint32_t>{0, 0, 0, 1, 1, 2, 2, 2, 2}));
    const std::uint32_t F = FirstOfPolyline, L = LastOfPolyline;
    EXPECT_EQ(s.flags, (std::vector<std::uint32_t>{F, 0, L, F, L, F, 0, 0, L}));
}

TEST(Styling, TwoVertexPolylineIsBothFirstAndLast) {
    LineSet lines;
    lines.positions = {{0, 0, 0}, {1, 0, 0}};
    lines.offsets = {0, 2};
    lines.updateBounds();
    StyledLines s = styleLines(lines, StyleSpec{}, "");
    EXPECT_EQ(s.flags[0], std::uint32_t(FirstOfPolyline));
    EXPECT_EQ(s.flags[1], std::uint32_t(LastOfPolyline));
}

TEST(Styling, BoundsIncludeTheRadii) {
    StyleSpec style;
    style.radius.attribute = "a";
    style.radius.radiusLo = 0.1f;
    style.radius.radiusHi = 0.9f;
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    // Vertex i has r = 0.1 + 0.1 i: lo.x from vertex 5 at (0,2,0), r 0.6; lo.y from vertex 2 at
    // (2,0,0), r 0.3; z from vertex 8 at (3,2,0), r 0.9, which also gives hi.x and hi.y.
    expectNear(s.bounds.lo, {-0.6f, -0.3f, -0.9f}, 1e-6f);
    expectNear(s.bounds.hi, {3.9f, 2.9f, 0.9f}, 1e-6f);
}

TEST(Styling, NanColourComesFromTheStyleElseThePresetElseGrey) {
    LineSet lines = threeLines();
    lines.attributes[0].values[3] = std::numeric_limits<float>::quiet_NaN();
    lines.attributes[0].updateRange();
    StyleSpec style;
    style.color.attribute = "a";
    Colormap preset = builtinColormap("grayscale");
    preset.nanColor = glm::vec3(1, 1, 0);
    style.color.colormap = "preset.json";
    style.color.preset = std::make_shared<const Colormap>(preset);
    expectNear(glm::vec3(styleLines(lines, style, "scene.json").color[3]), {1, 1, 0}, 1e-6f);
    style.color.nanColor = glm::vec3(0, 1, 1);
    expectNear(glm::vec3(styleLines(lines, style, "scene.json").color[3]), {0, 1, 1}, 1e-6f);
    // Non-NaN vertices come from the preset, not the built-in named "viridis" by default.
    expectNear(glm::vec3(styleLines(lines, style, "scene.json").color[8]), {1, 1, 1}, 1e-6f);
}

TEST(Styling, UnloadedPresetIsAnErrorNamingTheKey) {
    StyleSpec style;
    style.color.attribute = "a";
    style.color.colormap = "maps/blue.json";
    EXPECT_EQ(styleError(threeLines(), style),
              "scene.json: style.color.colormap: preset \"maps/blue.json\" was not loaded");
}

TEST(Styling, PercentileRangeIgnoresOutliers) {
    // a = 0..7 plus one outlier 1000 (9 values): numpy's linear percentiles are 4 at 50 and
    // 6 at 75, so [p0, p75] maps a = 0..6 and the outlier clamps to the top.
    LineSet lines = threeLines();
    lines.attributes[0].values[8] = 1000.0f;
    lines.attributes[0].updateRange();
    EXPECT_FLOAT_EQ(percentile(lines.attributes[0].values, 0.0f), 0.0f);
    EXPECT_FLOAT_EQ(percentile(lines.attributes[0].values, 50.0f), 4.0f);
    EXPECT_NEAR(percentile(lines.attributes[0].values, 75.0f), 6.0f, 1e-6f);
    EXPECT_FLOAT_EQ(percentile(lines.attributes[0].values, 100.0f), 1000.0f);
    EXPECT_TRUE(std::isnan(percentile({std::nanf("")}, 50.0f)));
    StyleSpec style;
    style.radius.attribute = "a";
    style.radius.range.percentiles = true;
    style.radius.range.percentileLo = 0.0f;
    style.radius.range.percentileHi = 75.0f;  // a = 0 .. 6
    style.radius.radiusLo = 1.0f;
    style.radius.radiusHi = 7.0f;
    StyledLines s = styleLines(lines, style, "scene.json");
    EXPECT_NEAR(s.positionRadius[3].w, 4.0f, 1e-5f);
    EXPECT_NEAR(s.positionRadius[6].w, 7.0f, 1e-5f);
    EXPECT_NEAR(s.positionRadius[8].w, 7.0f, 1e-5f);  // the outlier clamps
}

TEST(Styling, NanOpacityTakesTheLowEndOfTheTransferFunction) {
    LineSet lines = threeLines();
    lines.attributes[0].values[5] = std::numeric_limits<float>::quiet_NaN();
    lines.attributes[0].updateRange();
    StyleSpec style;
    style.opacity.attribute = "a";
    style.opacity.points = {{0.0f, 0.2f}, {1.0f, 0.9f}};
    EXPECT_FLOAT_EQ(styleLines(lines, style, "scene.json").color[5].w, 0.2f);
    EXPECT_FLOAT_EQ(evaluateTransferFunction(style.opacity.points, std::nanf("")), 0.2f);
}

TEST(Styling, OpacityPointsCanComeFromThePreset) {
    StyleSpec style;
    style.opacity.attribute = "a";
    style.opacity.pointsFromColormap = true;
    EXPECT_EQ(styleError(threeLines(), style),
              "scene.json: style.opacity.points: the colormap \"viridis\" has no opacity points");
    Colormap preset = builtinColormap("grayscale");
    preset.opacity = {{0.0f, 1.0f}, {1.0f, 0.0f}};
    style.color.colormap = "p.json";
    style.color.preset = std::make_shared<const Colormap>(preset);
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    EXPECT_NEAR(s.color[2].w, 0.75f, 1e-6f);  // t = 0.25
}

TEST(Styling, DerivedAttributesAreComputedWhenTheStyleNamesThem) {
    StyleSpec style;
    style.radius.attribute = "arc_length";  // polylines along x with unit steps: 0, 1, 2, ...
    style.radius.range = {false, 0.0f, 3.0f};
    style.radius.radiusLo = 0.0f;
    style.radius.radiusHi = 3.0f;
    style.color.attribute = "line_length";
    style.color.colormap = "grayscale";
    style.color.range = {false, 0.0f, 3.0f};
    StyledLines s = styleLines(threeLines(), style, "scene.json");
    const float arc[] = {0, 1, 2, 0, 1, 0, 1, 2, 3};
    for (std::size_t i = 0; i < 9; ++i) EXPECT_NEAR(s.positionRadius[i].w, arc[i], 1e-6f) << i;
    expectNear(glm::vec3(s.color[3]), glm::vec3(srgbToLinear(1.0f / 3.0f)), 1e-6f);  // length 1
    style = {};
    style.color.attribute = "speed";
    EXPECT_EQ(styleError(threeLines(), style),
              "scene.json: style.color.attribute: \"speed\" needs a velocity: an attribute \"velocity_magnitude\" or "
              "components velocity_x/_y/_z (or vel_*, v_*)");
}

TEST(Styling, TabulatedDivergingAndLabMapsMatchTheExactColours) {
    // styleLines tabulates non-RGB colormaps at t = k / 4096; the claim is 1e-5 of the exact
    // colour, including at and next to the diverging white point t = 0.5 (a kink).
    LineSet lines = threeLines();
    for (std::size_t i = 0; i < 9; ++i) lines.attributes[0].values[i] = std::pow(float(i) / 8.0f, 1.7f);
    lines.attributes[0].values[3] = 0.5f;
    lines.attributes[0].values[4] = 0.5f + 0.3f / 4096.0f;
    lines.attributes[0].updateRange();
    for (const char* name : {"cool_warm", "lab"}) {
        Colormap map = builtinColormap("cool_warm");
        if (std::string(name) == "lab") map.space = ColorSpace::Lab;
        StyleSpec style;
        style.color.attribute = "a";
        style.color.colormap = name;
        style.color.preset = std::make_shared<const Colormap>(map);
        StyledLines s = styleLines(lines, style, "scene.json");
        for (std::size_t i = 0; i < 9; ++i)
            expectNear(linearToSrgb(glm::vec3(s.color[i])), map.sampleSrgb(lines.attributes[0].values[i]), 1e-5f);
    }
}

TEST(Styling, EmptyLineSetGivesEmptyBuffers) {
    StyledLines s = styleLines(LineSet{}, StyleSpec{}, "scene.json");
    EXPECT_EQ(s.vertexCount(), 0u);
    EXPECT_EQ(s.segmentCount(), 0u);
    EXPECT_TRUE(s.bounds.empty());
}

}  // namespace
}  // namespace tc
