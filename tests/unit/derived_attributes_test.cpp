// Derived attributes (core/derived_attributes.h) against analytic values.
#include "core/derived_attributes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.h"

namespace tc {
namespace {

constexpr double kPi = std::numbers::pi;

void addPolyline(LineSet& lines, const std::vector<glm::vec3>& points) {
    lines.positions.insert(lines.positions.end(), points.begin(), points.end());
    lines.offsets.push_back(std::uint32_t(lines.positions.size()));
    lines.updateBounds();
}

// (a cos t, a sin t, c t) for t in [0, turns * 2 pi], `perTurn` samples per turn.
std::vector<glm::vec3> helix(double a, double c, int turns, int perTurn) {
    std::vector<glm::vec3> p;
    for (int i = 0; i <= turns * perTurn; ++i) {
        double t = 2 * kPi * i / perTurn;
        p.push_back(glm::vec3(glm::dvec3(a * std::cos(t), a * std::sin(t), c * t)));
    }
    return p;
}

TEST(DerivedAttributes, ArcLengthAndLineLengthOfAKnownPolyline) {
    LineSet lines;
    addPolyline(lines, {{0, 0, 0}, {3, 4, 0}, {3, 4, 12}});  // segments 5 and 12
    addPolyline(lines, {{1, 1, 1}, {1, 1, 2}});
    Attribute arc = computeDerivedAttribute(lines, "arc_length");
    Attribute total = computeDerivedAttribute(lines, "line_length");
    EXPECT_EQ(arc.values, (std::vector<float>{0, 5, 17, 0, 1}));
    EXPECT_EQ(total.values, (std::vector<float>{17, 17, 17, 1, 1}));
    EXPECT_EQ(arc.min, 0.0f);
    EXPECT_EQ(arc.max, 17.0f);
}

TEST(DerivedAttributes, CurvatureOfASampledCircleIsOneOverTheRadius) {
    // Menger curvature is exact for points on a circle; the tolerance covers float positions.
    for (double radius : {0.01, 1.0, 250.0}) {
        LineSet lines;
        std::vector<glm::vec3> circle;
        for (int i = 0; i < 50; ++i) {  // an open arc of 0.9 turns, irregular spacing
            double t = 2 * kPi * 0.9 * std::pow(i / 49.0, 1.3);
            // Centred off the origin by a few radii (positions are float: a far centre would
            // swamp a small circle's chords in rounding).
            circle.push_back(glm::vec3(radius * (glm::dvec3(std::cos(t), std::sin(t), 0.0) + glm::dvec3(3, -2, 7))));
        }
        addPolyline(lines, circle);
        Attribute k = computeDerivedAttribute(lines, "curvature");
        for (std::size_t i = 0; i < k.values.size(); ++i)
            EXPECT_NEAR(k.values[i] * radius, 1.0, 2e-3) << "radius " << radius << " vertex " << i;
    }
}

TEST(DerivedAttributes, StraightLinesAndShortPolylinesHaveNoCurvatureOrTorsion) {
    LineSet lines;
    addPolyline(lines, {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {5, 5, 5}, {6, 6, 6}});
    addPolyline(lines, {{0, 0, 0}, {1, 0, 0}});
    for (const char* name : {"curvature", "torsion"})
        for (float v : computeDerivedAttribute(lines, name).values) EXPECT_EQ(v, 0.0f) << name;
}

TEST(DerivedAttributes, TorsionOfAHelixIsCOverASquaredPlusCSquared) {
    // tau = c / (a^2 + c^2) for (a cos t, a sin t, c t): right-handed for c > 0. The discrete
    // binormal angle converges quadratically in the sampling step: 100 samples per turn
    // give well under 1 %. Curvature of the same helix: kappa = a / (a^2 + c^2).
    for (double c : {0.5, -0.5, 2.0}) {
        const double a = 1.5;
        LineSet lines;
        addPolyline(lines, helix(a, c, 3, 100));
        Attribute tau = computeDerivedAttribute(lines, "torsion");
        Attribute kappa = computeDerivedAttribute(lines, "curvature");
        const double expectedTau = c / (a * a + c * c), expectedKappa = a / (a * a + c * c);
        for (std::size_t i = 0; i < tau.values.size(); ++i) {
            EXPECT_NEAR(tau.values[i], expectedTau, 0.01 * std::abs(expectedTau)) << "c " << c << " vertex " << i;
            EXPECT_NEAR(kappa.values[i], expectedKappa, 0.01 * expectedKappa) << "c " << c << " vertex " << i;
        }
    }
}

TEST(DerivedAttributes, TorsionOfAPlanarCurveIsZero) {
    LineSet lines;
    std::vector<glm::vec3> wave;
    for (int i = 0; i < 60; ++i) wave.push_back({0.1f * float(i), std::sin(0.3f * float(i)), 2.0f});
    addPolyline(lines, wave);
    for (float v : computeDerivedAttribute(lines, "torsion").values) EXPECT_NEAR(v, 0.0f, 1e-4f);
}

TEST(DerivedAttributes, LocalDensityCountsDistinctLinesPerVoxel) {
    // A unit square domain (voxel 1/64): a bundle of 5 lines within one voxel row along x at
    // y = 0.19 .. 0.194 (voxel row 12 is [0.1875, 0.203)), a lone line along x at y = 0.8, and
    // a line along y at x = 0.5 crossing both.
    LineSet lines;
    auto straight = [](glm::vec3 from, glm::vec3 to) {
        std::vector<glm::vec3> p;
        for (int i = 0; i <= 10; ++i) p.push_back(glm::mix(from, to, float(i) / 10.0f));
        return p;
    };
    for (int k = 0; k < 5; ++k)
        addPolyline(lines, straight({0.01f, 0.19f + 1e-3f * k, 0}, {0.99f, 0.19f + 1e-3f * k, 0}));
    addPolyline(lines, straight({0.01f, 0.8f, 0}, {0.99f, 0.8f, 0}));
    addPolyline(lines, straight({0.5f, 0.0f, 0}, {0.5f, 1.0f, 0}));  // sets the bounds to [0, 1] in y
    // A zigzag inside one voxel near the corner counts once there.
    addPolyline(lines, {{0.995f, 0.995f, 0}, {0.999f, 0.996f, 0}, {0.995f, 0.997f, 0}, {0.999f, 0.998f, 0}});
    lines.updateBounds();
    Attribute d = computeDerivedAttribute(lines, "local_density");
    auto at = [&](std::size_t polyline, std::size_t vertex) { return d.values[lines.offsets[polyline] + vertex]; };
    for (std::size_t p = 0; p < 5; ++p) {
        EXPECT_EQ(at(p, 0), 5.0f) << "bundle line " << p;
        EXPECT_EQ(at(p, 3), 5.0f) << "bundle line " << p;
    }
    EXPECT_EQ(at(5, 0), 1.0f);  // the lone line
    EXPECT_EQ(at(6, 0), 1.0f);  // the crossing line, away from the others
    EXPECT_EQ(at(6, 2), 6.0f);  // (0.5, 0.2): the bundle's voxel plus itself
    EXPECT_EQ(at(6, 8), 2.0f);  // (0.5, 0.8): the lone line's voxel plus itself
    EXPECT_EQ(at(7, 2), 1.0f);  // the zigzag
}

TEST(DerivedAttributes, SpeedComesFromVelocityComponents) {
    LineSet lines;
    addPolyline(lines, {{0, 0, 0}, {1, 0, 0}});
    lines.attributes = {{"velocity_x", {3, 0}}, {"velocity_y", {4, 0}}, {"velocity_z", {0, -2}}};
    EXPECT_EQ(computeDerivedAttribute(lines, "speed").values, (std::vector<float>{5, 2}));
    lines.attributes.push_back({"velocity_magnitude", {7, 8}});
    EXPECT_EQ(computeDerivedAttribute(lines, "speed").values, (std::vector<float>{7, 8}));
    lines.attributes.clear();
    EXPECT_THROW(computeDerivedAttribute(lines, "speed"), InputError);
}

TEST(DerivedAttributes, DatasetAttributesWinAndOnlyNamedOnesAreAdded) {
    LineSet lines;
    addPolyline(lines, {{0, 0, 0}, {2, 0, 0}});
    lines.attributes = {{"arc_length", {42, 43}}};
    addDerivedAttributes(lines, {"arc_length", "line_length", "not_derived"});
    ASSERT_EQ(lines.attributes.size(), 2u);
    EXPECT_EQ(lines.attributes[0].values, (std::vector<float>{42, 43}));
    EXPECT_EQ(lines.attributes[1].name, "line_length");
    EXPECT_EQ(lines.attributes[1].values, (std::vector<float>{2, 2}));
}

}  // namespace
}  // namespace tc
