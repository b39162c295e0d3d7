// Built-in generators (core/generators.h): the tornado streamlines are deterministic, in the
// unit cube and evenly spaced; the benchmark stand-ins (propeller, brain, convection, turbulence)
// and the spirals are deterministic, have the documented sizes, stay in their domains and follow their fields.
#include "core/generators.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>

#include "core/scene.h"

namespace tc {
namespace {

TEST(Generators, TornadoIsDeterministicForASeed) {
    LineSet a = generateTornado(50, 80, 7);
    LineSet b = generateTornado(50, 80, 7);
    EXPECT_EQ(a.offsets, b.offsets);
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) ASSERT_EQ(a.positions[i], b.positions[i]) << "vertex " << i;
    ASSERT_EQ(a.attributes.size(), b.attributes.size());
    for (std::size_t k = 0; k < a.attributes.size(); ++k) EXPECT_EQ(a.attributes[k].values, b.attributes[k].values);
}

TEST(Generators, TornadoDiffersBetweenSeeds) {
    LineSet a = generateTornado(20, 50, 1);
    LineSet b = generateTornado(20, 50, 2);
    ASSERT_FALSE(a.positions.empty());
    ASSERT_FALSE(b.positions.empty());
    EXPECT_NE(a.positions.front(), b.positions.front());
}

TEST(Generators, TornadoHasTheRequestedNumberOfPolylinesOfAtMostPointsVertices) {
    const int lines = 120, points = 150;
    LineSet set = generateTornado(lines, points, 3);
    EXPECT_EQ(set.polylineCount(), std::size_t(lines));
    EXPECT_EQ(set.offsets.back(), set.vertexCount());
    for (std::size_t p = 0; p < set.polylineCount(); ++p) {
        std::uint32_t n = set.offsets[p + 1] - set.offsets[p];
        EXPECT_GE(n, 2u) << "polyline " << p;
        EXPECT_LE(n, std::uint32_t(points)) << "polyline " << p;
    }
}

TEST(Generators, TornadoStreamlinesEndEarlyOnlyAtTheCubeFaces) {
    // A streamline shorter than `points` stopped because its next step would leave the unit cube
    // (every re-seed did too), so its last vertex is within one step of a face. Note that many
    // streamlines are shorter: lines x points is an upper bound of the vertex count.
    const int points = 200;
    const float step = 3.0f / float(points - 1);
    LineSet set = generateTornado(200, points, 1);
    std::size_t shorter = 0;
    for (std::size_t p = 0; p < set.polylineCount(); ++p) {
        if (set.offsets[p + 1] - set.offsets[p] == std::uint32_t(points)) continue;
        ++shorter;
        glm::vec3 q = set.positions[set.offsets[p + 1] - 1];
        float toFace = std::min({q.x, q.y, q.z, 1 - q.x, 1 - q.y, 1 - q.z});
        EXPECT_LE(toFace, step) << "polyline " << p << " ends at " << q.x << ", " << q.y << ", " << q.z;
    }
    EXPECT_LT(shorter, set.polylineCount());
}

TEST(Generators, TornadoVerticesAreInsideTheUnitCube) {
    LineSet set = generateTornado(200, 200, 1);
    for (const glm::vec3& p : set.positions) {
        ASSERT_TRUE(p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1 && p.z >= 0 && p.z <= 1)
            << p.x << ", " << p.y << ", " << p.z;
    }
    EXPECT_GE(set.bounds.lo.x, 0.0f);
    EXPECT_LE(set.bounds.hi.z, 1.0f);
    EXPECT_FALSE(set.bounds.empty());
}

TEST(Generators, TornadoVerticesAreEvenlySpacedAtTheArcLengthStep) {
    // Streamlines cover an arc length of up to 3 at any resolution: step = 3 / (points - 1). An
    // RK4 step of the unit-speed field is an arc of that length, so the chord between vertices
    // is the step, shortened only where the curvature is high relative to the step (a few per
    // cent at 200 points and more; the core of the vortex has a radius of about 0.1).
    for (int points : {200, 501}) {
        const float step = 3.0f / float(points - 1);
        LineSet set = generateTornado(60, points, 5);
        float lo = 1e30f, hi = 0.0f;
        double sum = 0;
        for (std::size_t p = 0; p < set.polylineCount(); ++p)
            for (std::uint32_t v = set.offsets[p] + 1; v < set.offsets[p + 1]; ++v) {
                float d = glm::length(set.positions[v] - set.positions[v - 1]);
                lo = std::min(lo, d);
                hi = std::max(hi, d);
                sum += d;
            }
        EXPECT_LE(hi, step * 1.001f) << "points " << points;
        EXPECT_GE(lo, step * 0.9f) << "points " << points;
        EXPECT_NEAR(sum / double(set.segmentCount()), step, 0.005 * step) << "points " << points;
    }
}

TEST(Generators, TornadoAttributesArePresentWithFiniteRanges) {
    LineSet set = generateTornado(40, 60, 1);
    for (const char* name : {"speed", "height", "arc_length"}) {
        const Attribute* a = set.attribute(name);
        ASSERT_NE(a, nullptr) << name;
        EXPECT_EQ(a->values.size(), set.vertexCount()) << name;
        EXPECT_TRUE(std::isfinite(a->min) && std::isfinite(a->max)) << name;
        EXPECT_LT(a->min, a->max) << name;
    }
    // height is z; arc_length starts at 0 on every polyline and increases.
    const Attribute& height = *set.attribute("height");
    const Attribute& arc = *set.attribute("arc_length");
    for (std::size_t v = 0; v < set.vertexCount(); ++v) EXPECT_EQ(height.values[v], set.positions[v].z);
    for (std::size_t p = 0; p < set.polylineCount(); ++p) {
        EXPECT_EQ(arc.values[set.offsets[p]], 0.0f);
        for (std::uint32_t v = set.offsets[p] + 1; v < set.offsets[p + 1]; ++v)
            EXPECT_GT(arc.values[v], arc.values[v - 1]);
    }
    EXPECT_GE(set.attribute("speed")->min, 0.0f);
}

TEST(Generators, TornadoVelocityIsFiniteOnAGridIncludingTheFaces) {
    const int n = 32;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            for (int k = 0; k <= n; ++k) {
                glm::vec3 p{float(i) / n, float(j) / n, float(k) / n};
                glm::vec3 v = tornadoVelocity(p);
                ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z))
                    << "at " << p.x << ", " << p.y << ", " << p.z;
            }
}

TEST(Generators, TornadoVelocitySwirlsAboutTheCoreAndRises) {
    // Near the core at mid height the flow circles the core (tangential component dominates the
    // radial one) and drifts upward.
    const float z = 0.5f;
    glm::vec3 core{0.5f + 0.1f * std::sin(10.0f * z), 0.5f + 0.1f * std::cos(3.0f * z), z};
    glm::vec3 p = core + glm::vec3(0.15f, 0.0f, 0.0f);
    glm::vec3 v = tornadoVelocity(p);
    EXPECT_GT(std::abs(v.y), 2.0f * std::abs(v.x));
    EXPECT_GT(v.z, 0.0f);
}

// configs/tornado_1m.json is the 1,000,000-segment benchmark of docs/performance.md ("Rasterized
// lines"). Streamlines that leave the cube are shorter than `points`, so its line count was chosen
// by generating; this keeps it honest when the generator changes.
TEST(Generators, TornadoBenchmarkConfigHasAboutAMillionSegments) {
    std::filesystem::path config =
        std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "configs" / "tornado_1m.json";
    Scene scene = loadScene(config.string());
    LineSet set = generateTornado(scene.dataset.lines, scene.dataset.points, scene.dataset.seed);
    EXPECT_GE(set.segmentCount(), 1'000'000u);
    EXPECT_LE(set.segmentCount(), 1'010'000u);
}

// The stand-ins -------------------------------------------------------------------------------

void expectIdentical(const LineSet& a, const LineSet& b) {
    ASSERT_EQ(a.offsets, b.offsets);
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) ASSERT_EQ(a.positions[i], b.positions[i]) << "vertex " << i;
    ASSERT_EQ(a.attributes.size(), b.attributes.size());
    for (std::size_t k = 0; k < a.attributes.size(); ++k) {
        EXPECT_EQ(a.attributes[k].name, b.attributes[k].name);
        EXPECT_EQ(a.attributes[k].values, b.attributes[k].values) << a.attributes[k].name;
    }
}

class StandIn : public ::testing::TestWithParam<const char*> {};

TEST_P(StandIn, IsDeterministicForASeedAndIndependentOfTheThreadCount) {
    LineSet many = generateDataset(GetParam(), 300, 40, 7);
    LineSet one;
    {
        tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
        one = generateDataset(GetParam(), 300, 40, 7);
    }
    expectIdentical(many, one);
    LineSet other = generateDataset(GetParam(), 300, 40, 8);
    EXPECT_NE(many.positions, other.positions);
}

TEST_P(StandIn, HasAttributesForEveryVertexWithFiniteRanges) {
    LineSet set = generateDataset(GetParam(), 100, 50, 1);
    ASSERT_GE(set.attributes.size(), 2u);
    for (const Attribute& a : set.attributes) {
        EXPECT_EQ(a.values.size(), set.vertexCount()) << a.name;
        EXPECT_TRUE(std::isfinite(a.min) && std::isfinite(a.max)) << a.name;
        EXPECT_LT(a.min, a.max) << a.name;
    }
}

TEST_P(StandIn, PolylinesAreValidLineSets) {
    // The LineSet invariants the renderer relies on: >= 2 vertices, no zero-length segment.
    LineSet set = generateDataset(GetParam(), 200, 60, 3);
    EXPECT_EQ(set.offsets.back(), set.vertexCount());
    for (std::size_t p = 0; p < set.polylineCount(); ++p) {
        ASSERT_GE(set.offsets[p + 1] - set.offsets[p], 2u) << "polyline " << p;
        for (std::uint32_t v = set.offsets[p] + 1; v < set.offsets[p + 1]; ++v)
            ASSERT_GT(glm::length(set.positions[v] - set.positions[v - 1]), 0.0f) << "vertex " << v;
    }
}

INSTANTIATE_TEST_SUITE_P(Generators, StandIn,
                         ::testing::Values("propeller", "brain", "convection", "turbulence", "spiral"));

TEST(Generators, StandInsWithFixedLengthsHaveLinesTimesPointsMinusOneSegments) {
    for (const char* name : {"propeller", "brain", "convection", "spiral"}) {
        for (auto [lines, points] : {std::pair{1, 2}, std::pair{37, 11}, std::pair{250, 64}}) {
            LineSet set = generateDataset(name, lines, points, 2);
            EXPECT_EQ(set.polylineCount(), std::size_t(lines)) << name;
            EXPECT_EQ(set.segmentCount(), std::size_t(lines) * std::size_t(points - 1)) << name;
        }
    }
}

TEST(Generators, TurbulenceLosesOnlyTheSegmentsThatCrossAFace) {
    // Exactly lines x points vertices are traced; a polyline is cut where the line leaves the
    // periodic cube, so every cut removes one segment. Count the cuts independently: the two
    // polylines at a cut are one step apart modulo the period (a step is ~0.005-0.01 here),
    // while the start of another line is a random point.
    const int lines = 300, points = 200;
    LineSet set = generateDataset("turbulence", lines, points, 4);
    std::size_t jumps = 0;
    for (std::size_t p = 1; p < set.polylineCount(); ++p) {
        glm::vec3 d = set.positions[set.offsets[p]] - set.positions[set.offsets[p] - 1];
        glm::vec3 wrapped = glm::abs(d - glm::round(d));
        if (std::max({wrapped.x, wrapped.y, wrapped.z}) < 0.06f && glm::length(d) > 0.5f) ++jumps;
    }
    // Not exact: a dropped single-vertex piece (a line clipping a cube edge) loses two segments
    // but leaves one adjacency, and a far-off start of another line could pass the test.
    const std::size_t traced = std::size_t(lines) * std::size_t(points - 1);
    EXPECT_GE(set.polylineCount(), std::size_t(lines));
    EXPECT_NEAR(double(set.segmentCount() + jumps), double(traced), 10.0);
    EXPECT_LE(set.segmentCount(), traced);
    // About one cube length of arc per line: most lines cross a face at most a few times.
    EXPECT_GT(set.segmentCount(), traced * 97 / 100);
}

TEST(Generators, StandInsStayInTheirDocumentedDomains) {
    {
        LineSet set = generatePropeller(300, 200, 1);
        for (const glm::vec3& p : set.positions) {
            ASSERT_LE(glm::length(glm::vec2(p.x - 0.5f, p.y - 0.5f)), 0.42f + 1e-4f) << p.x << ", " << p.y;
            ASSERT_TRUE(p.z >= 0.01f && p.z <= 0.98f) << p.z;
        }
    }
    {
        LineSet set = generateBrain(2000, 30, 1);
        for (const glm::vec3& p : set.positions) ASSERT_TRUE(insideBrain(p)) << p.x << ", " << p.y << ", " << p.z;
    }
    {
        LineSet set = generateConvection(300, 200, 1);
        for (const glm::vec3& p : set.positions)
            ASSERT_TRUE(p.x >= 0 && p.x <= 1 && p.y >= 0.005f && p.y <= 0.995f && p.z >= 0 && p.z <= kConvectionHeight)
                << p.x << ", " << p.y << ", " << p.z;
    }
    {
        LineSet set = generateTurbulence(300, 200, 1);
        for (const glm::vec3& p : set.positions)
            ASSERT_TRUE(p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1 && p.z >= 0 && p.z <= 1)
                << p.x << ", " << p.y << ", " << p.z;
    }
}

TEST(Generators, SpiralsLieOnTheirShellsInsideTheBallAndFillIt) {
    // The benchmark's 2000 x 500 spiral set: 998,000 segments, every vertex at its line's shell
    // radius from the centre, shells spanning 0.15..0.5, and (3 turns each) all polar directions.
    LineSet set = generateSpiral(2000, 500, 1);
    EXPECT_EQ(set.polylineCount(), 2000u);
    EXPECT_EQ(set.segmentCount(), 998'000u);
    const Attribute& shell = set.attributes[0];
    ASSERT_EQ(shell.name, "shell");
    for (std::size_t v = 0; v < set.vertexCount(); ++v) {
        const float r = glm::length(set.positions[v] - glm::vec3(0.5f));
        ASSERT_NEAR(r, shell.values[v], 1e-5f) << "vertex " << v;
        ASSERT_TRUE(r >= kSpiralMinShell - 1e-5f && r <= kSpiralMaxShell + 1e-5f) << "vertex " << v << ": " << r;
    }
    EXPECT_LT(shell.min, kSpiralMinShell + 0.01f);
    EXPECT_GT(shell.max, kSpiralMaxShell - 0.01f);
    // The bounds reach the ball's extent on every axis (random axes, so some line passes near each
    // pole of the ball) and never beyond.
    for (int a = 0; a < 3; ++a) {
        EXPECT_LT(set.bounds.lo[a], 0.02f) << a;
        EXPECT_GE(set.bounds.lo[a], 0.0f - 1e-5f) << a;
        EXPECT_GT(set.bounds.hi[a], 0.98f) << a;
        EXPECT_LE(set.bounds.hi[a], 1.0f + 1e-5f) << a;
    }
    // Segments are short against the tube radius of the benchmark (0.004) times a few: the spiral
    // is smooth at 500 points.
    float longest = 0.0f;
    for (std::size_t p = 0; p < set.polylineCount(); ++p)
        for (std::uint32_t v = set.offsets[p] + 1; v < set.offsets[p + 1]; ++v)
            longest = std::max(longest, glm::length(set.positions[v] - set.positions[v - 1]));
    EXPECT_LT(longest, 0.03f);
}

// Central-difference tangents against the field's direction at interior vertices.
void expectFollows(const LineSet& set, const std::function<glm::vec3(std::size_t vertex)>& field, const char* name) {
    std::size_t checked = 0;
    float worst = 1.0f;
    for (std::size_t p = 0; p < set.polylineCount(); ++p)
        for (std::uint32_t v = set.offsets[p] + 1; v + 1 < set.offsets[p + 1]; v += 7) {
            glm::vec3 tangent = set.positions[v + 1] - set.positions[v - 1];
            glm::vec3 f = field(v);
            ASSERT_GT(glm::length(f), 0.0f) << name << " vertex " << v;
            float c = glm::dot(glm::normalize(tangent), glm::normalize(f));
            worst = std::min(worst, c);
            ++checked;
        }
    EXPECT_GT(checked, 500u) << name;
    EXPECT_GT(worst, 0.99f) << name;
}

TEST(Generators, StandInStreamlinesFollowTheirFields) {
    LineSet propeller = generatePropeller(200, 300, 1);
    expectFollows(
        propeller, [&](std::size_t v) { return propellerVelocity(propeller.positions[v]); }, "propeller");
    LineSet convection = generateConvection(200, 300, 1);
    expectFollows(
        convection, [&](std::size_t v) { return convectionVelocity(convection.positions[v]); }, "convection");
    LineSet turbulence = generateTurbulence(200, 300, 1);
    expectFollows(
        turbulence, [&](std::size_t v) { return turbulenceVelocity(turbulence.positions[v]); }, "turbulence");
    LineSet brain = generateBrain(500, 30, 1);
    const Attribute& bundle = *brain.attribute("bundle");
    expectFollows(
        brain, [&](std::size_t v) { return brainBundleDirection(int(bundle.values[v]), brain.positions[v]); }, "brain");
}

TEST(Generators, ConvectionRollsAreDivergenceFreeAndTangentToTheWalls) {
    // The stream-function construction: zero normal velocity on every roll wall and on the
    // bottom and top, and zero divergence inside (central differences).
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j) {
            float s = float(i) / 8, t = float(j) / 8;
            EXPECT_NEAR(convectionVelocity({0.25f * float(i % 5), t, s * kConvectionHeight}).x, 0.0f, 1e-5f);
            EXPECT_NEAR(convectionVelocity({s, t, 0.0f}).z, 0.0f, 1e-6f);
            EXPECT_NEAR(convectionVelocity({s, t, kConvectionHeight}).z, 0.0f, 1e-5f);
            glm::vec3 p{0.05f + 0.9f * s, t, (0.05f + 0.9f * float((i * 3 + j) % 9) / 8) * kConvectionHeight};
            const float e = 1e-3f;
            float div = (convectionVelocity(p + glm::vec3(e, 0, 0)).x - convectionVelocity(p - glm::vec3(e, 0, 0)).x +
                         convectionVelocity(p + glm::vec3(0, e, 0)).y - convectionVelocity(p - glm::vec3(0, e, 0)).y +
                         convectionVelocity(p + glm::vec3(0, 0, e)).z - convectionVelocity(p - glm::vec3(0, 0, e)).z) /
                        (2 * e);
            EXPECT_NEAR(div, 0.0f, 2e-2f) << p.x << ", " << p.z;
        }
}

TEST(Generators, TurbulenceFieldIsPeriodicOverTheUnitCube) {
    for (int i = 0; i < 20; ++i) {
        glm::vec3 p{0.05f * float(i), 0.37f + 0.01f * float(i), 0.91f - 0.04f * float(i)};
        glm::vec3 a = turbulenceVelocity(p), b = turbulenceVelocity(p + glm::vec3(1, 0, -1));
        EXPECT_LT(glm::length(a - b), 1e-3f * glm::length(a) + 1e-4f);
    }
}

TEST(Generators, BrainFibersAreShortCurvedAndGroupedInBundles) {
    LineSet set = generateBrain(3000, 21, 5);
    const Attribute& arc = *set.attribute("arc_length");
    const Attribute& bundle = *set.attribute("bundle");
    std::vector<int> perBundle(kBrainBundles, 0);
    double meanLength = 0;
    std::size_t curved = 0;
    for (std::size_t p = 0; p < set.polylineCount(); ++p) {
        std::uint32_t first = set.offsets[p], last = set.offsets[p + 1] - 1;
        float length = arc.values[last];
        meanLength += length;
        ++perBundle[std::size_t(bundle.values[first])];
        // Chord shorter than the arc: the fiber bends (an arc of length 0.1 on the widest
        // radius, 0.55, has chord / arc = 0.9986).
        if (glm::length(set.positions[last] - set.positions[first]) < 0.999f * length) ++curved;
    }
    meanLength /= double(set.polylineCount());
    EXPECT_GT(meanLength, 0.08);
    EXPECT_LT(meanLength, 0.4);
    EXPECT_GT(curved, set.polylineCount() * 9 / 10);
    for (int b = 0; b < kBrainBundles; ++b) EXPECT_GT(perBundle[std::size_t(b)], 50) << "bundle " << b;
}

TEST(Generators, TornadoThroughGenerateDatasetIsUnchanged) {
    expectIdentical(generateDataset("tornado", 50, 80, 7), generateTornado(50, 80, 7));
    EXPECT_THROW(generateDataset("hurricane", 1, 2, 1), std::invalid_argument);
}

}  // namespace
}  // namespace tc
