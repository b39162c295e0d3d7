// Density voxelization for line ambient occlusion (core/voxel_density.h): analytic volumes,
// clamping, face/edge tie-breaking, grid sizing, trilinear sampling, thread-count independence.
#include "core/voxel_density.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "core/error.h"
#include "core/generators.h"
#include "core/scene.h"
#include "core/styling.h"

using namespace tc;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Error budget of a voxelized total against the analytic volume: every voxel's float conversion
// is off by at most 2^-24 of its value (6e-8 of the total summed over voxels), every deposit by at
// most half a fixed-point unit (2^-33 = 1.2e-10 voxel volumes; a few 10^4 deposits here, so
// < 1e-5 absolute against totals of 10^2..10^4), the double arithmetic by ~1e-15. 1e-6 of the
// total leaves a margin of ~10 over that.
constexpr double kRelativeTolerance = 1e-6;

// Bounds [0,1] x [0,0.5] x [0,0.75] at resolution 17: voxel size 1/16 and origin -1/32 on every
// axis, so voxel faces are exact binary fractions and a segment placed on a face is exactly on it.
Bounds testBounds() {
    Bounds b;
    b.extend({0.0f, 0.0f, 0.0f});
    b.extend({1.0f, 0.5f, 0.75f});
    return b;
}
constexpr int kTestResolution = 17;

struct Segment {
    glm::vec3 a, b;
    float ra, rb;          // radii
    float alphaA, alphaB;  // opacities
};

StyledLines makeLines(const std::vector<Segment>& segments) {
    StyledLines lines;
    for (const Segment& s : segments) {
        const auto first = std::uint32_t(lines.positionRadius.size());
        lines.positionRadius.push_back({s.a, s.ra});
        lines.positionRadius.push_back({s.b, s.rb});
        lines.color.push_back({1.0f, 1.0f, 1.0f, s.alphaA});
        lines.color.push_back({1.0f, 1.0f, 1.0f, s.alphaB});
        lines.polylineId.insert(lines.polylineId.end(), 2, first / 2);
        lines.flags.push_back(FirstOfPolyline);
        lines.flags.push_back(LastOfPolyline);
        lines.segmentVertices.push_back(first);
        lines.segmentVertices.push_back(first + 1);
        lines.bounds.extend(s.a, s.ra);
        lines.bounds.extend(s.b, s.rb);
        lines.maxRadius = std::max({lines.maxRadius, s.ra, s.rb});
    }
    return lines;
}

// The part of segment s inside the grid as parameters [s0, s1] of [0,1], computed independently of
// the implementation (world coordinates); false when none of it is inside.
bool clipToGrid(const Segment& s, const DensityGrid& grid, double& s0, double& s1) {
    const glm::dvec3 lo(grid.origin), hi = lo + glm::dvec3(grid.size) * double(grid.voxelSize);
    const glm::dvec3 a(s.a), d = glm::dvec3(s.b) - a;
    s0 = 0.0;
    s1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (a[k] < lo[k] || a[k] > hi[k]) return false;
            continue;
        }
        double t0 = (lo[k] - a[k]) / d[k], t1 = (hi[k] - a[k]) / d[k];
        if (t0 > t1) std::swap(t0, t1);
        s0 = std::max(s0, t0);
        s1 = std::min(s1, t1);
    }
    return s0 <= s1;
}

// pi L * integral_{s0}^{s1} r(s)^2 a(s) ds / voxelSize^3 through the expanded cubic's
// antiderivative (the implementation uses Simpson's rule, so this is an independent formula).
double analyticDensity(const Segment& s, double s0, double s1, double voxelSize) {
    const double ra = s.ra, dr = double(s.rb) - s.ra, oa = s.alphaA, dO = double(s.alphaB) - s.alphaA;
    const double c[4] = {ra * ra * oa, ra * ra * dO + 2.0 * ra * dr * oa, 2.0 * ra * dr * dO + dr * dr * oa,
                         dr * dr * dO};
    double integral = 0.0;
    for (int i = 0; i < 4; ++i) integral += c[i] * (std::pow(s1, i + 1) - std::pow(s0, i + 1)) / (i + 1);
    const double length = glm::length(glm::dvec3(s.b) - glm::dvec3(s.a));
    return kPi * length * integral / (voxelSize * voxelSize * voxelSize);
}

// World position of grid coordinate g (voxel v covers [v, v + 1)).
glm::vec3 gridPoint(const DensityGrid& grid, const glm::vec3& g) {
    return grid.origin + g * grid.voxelSize;
}

std::size_t nonZeroVoxels(const DensityGrid& grid) {
    return std::size_t(std::count_if(grid.density.begin(), grid.density.end(), [](float d) { return d != 0.0f; }));
}

}  // namespace

TEST(VoxelDensity, GridHasResolutionAlongTheLongestAxisCubicVoxelsAndOthersFitted) {
    DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
    EXPECT_EQ(grid.size, glm::ivec3(17, 9, 13));
    EXPECT_EQ(grid.voxelSize, 1.0f / 16.0f);
    EXPECT_EQ(grid.origin, glm::vec3(-1.0f / 32.0f));
    EXPECT_EQ(grid.density.size(), 17u * 9u * 13u);
    EXPECT_EQ(grid.bytes(), 17u * 9u * 13u * 4u);
    EXPECT_EQ(grid.accumulatorBytes(), 24u * 16u * 16u * 8u);  // bricks of 8^3
    EXPECT_EQ(grid.total(), 0.0);

    // Longest axis z, non-power-of-two sizes: still `resolution` along it, and the bounds lie at
    // least half a voxel inside the grid on every side.
    Bounds b;
    b.extend({-3.0f, 1.0f, 2.0f});
    b.extend({0.7f, 1.9f, 12.3f});
    grid = makeDensityGrid(b, 256);
    EXPECT_EQ(grid.size.z, 256);
    EXPECT_FLOAT_EQ(grid.voxelSize, 10.3f / 255.0f);
    EXPECT_EQ(grid.size.x, int(std::ceil(3.7f / grid.voxelSize)) + 1);
    EXPECT_EQ(grid.size.y, int(std::ceil(0.9f / grid.voxelSize)) + 1);
    for (int k = 0; k < 3; ++k) {
        EXPECT_GE(b.lo[k] - grid.origin[k], 0.5f * grid.voxelSize * (1.0f - 1e-5f)) << k;
        EXPECT_GE(grid.hi()[k] - b.hi[k], 0.5f * grid.voxelSize * (1.0f - 1e-5f)) << k;
    }
}

TEST(VoxelDensity, FlatAndPointBoundsGiveAValidGrid) {
    Bounds flat;
    flat.extend({0.0f, 0.0f, 1.0f});
    flat.extend({2.0f, 1.0f, 1.0f});
    DensityGrid grid = makeDensityGrid(flat, 9);
    EXPECT_EQ(grid.size, glm::ivec3(9, 5, 1));
    EXPECT_EQ(grid.voxelSize, 0.25f);

    Bounds point;
    point.extend({1.0f, 2.0f, 3.0f});
    grid = makeDensityGrid(point, 4);
    EXPECT_EQ(grid.size, glm::ivec3(4, 1, 1));
    EXPECT_GT(grid.voxelSize, 0.0f);
    EXPECT_THROW(makeDensityGrid(Bounds{}, 4), Error);
    EXPECT_THROW(makeDensityGrid(flat, 1), Error);
}

TEST(VoxelDensity, TotalEqualsAnalyticConeVolumeTimesOpacityForRandomSegmentsIncludingFacesEdgesAndClamped) {
    DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
    std::mt19937 rng(20200504);
    std::uniform_real_distribution<float> inside(0.0f, 1.0f), outside(-0.6f, 1.6f), radius(0.002f, 0.05f),
        alpha(0.0f, 1.0f);
    std::uniform_int_distribution<int> face(0, 8);
    const glm::vec3 gridSize(grid.size);
    auto randomInside = [&] { return gridPoint(grid, glm::vec3(inside(rng), inside(rng), inside(rng)) * gridSize); };
    auto snap = [&](glm::vec3 p, int axis) {  // onto a voxel face along `axis`
        p[axis] = grid.origin[axis] + float(std::min(face(rng), grid.size[axis])) * grid.voxelSize;
        return p;
    };

    std::vector<Segment> segments;
    auto add = [&](glm::vec3 a, glm::vec3 b) {
        segments.push_back({a, b, radius(rng), radius(rng), alpha(rng), alpha(rng)});
    };
    for (int i = 0; i < 300; ++i) {
        add(randomInside(), randomInside());  // general
        const int axis = i % 3, other = (i + 1) % 3;
        glm::vec3 a = snap(randomInside(), axis), b = randomInside();
        b[axis] = a[axis];
        add(a, b);  // on a face
        a = snap(snap(randomInside(), axis), other);
        b = a;
        b[(i + 2) % 3] = randomInside()[(i + 2) % 3];
        add(a, b);  // on an edge
        a = randomInside();
        b = a;
        b[axis] = randomInside()[axis];
        add(a, b);  // axis-aligned
        a = randomInside();
        add(a, a);  // zero length
        add(gridPoint(grid, glm::vec3(outside(rng), outside(rng), outside(rng)) * gridSize),
            gridPoint(grid, glm::vec3(outside(rng), outside(rng), outside(rng)) * gridSize));  // partly outside
    }
    // Diagonals through voxel corners and edges (ties in the DDA), in both directions.
    add(gridPoint(grid, {1, 1, 1}), gridPoint(grid, {8, 8, 8}));
    add(gridPoint(grid, {8, 8, 2.5f}), gridPoint(grid, {2, 2, 2.5f}));
    // On the grid's outer faces and edges (inside the closed box).
    add(gridPoint(grid, {0, 0, 0}), gridPoint(grid, {17, 0, 0}));
    add(gridPoint(grid, {3, 9, 13}), gridPoint(grid, {11, 9, 13}));
    add(gridPoint(grid, {17, 2, 3}), gridPoint(grid, {17, 8, 12}));
    // Entirely outside.
    add(gridPoint(grid, {18, 2, 3}), gridPoint(grid, {25, 8, 12}));
    add(gridPoint(grid, {-5, -1, 3}), gridPoint(grid, {-5, 20, 3}));

    double expected = 0.0;
    std::size_t expectedClamped = 0;
    for (const Segment& s : segments) {
        double s0, s1;
        if (!clipToGrid(s, grid, s0, s1)) {
            ++expectedClamped;
            continue;
        }
        if (s0 > 0.0 || s1 < 1.0) ++expectedClamped;
        expected += analyticDensity(s, s0, s1, grid.voxelSize);
    }
    voxelizeLines(makeLines(segments), grid);
    EXPECT_NEAR(grid.total(), expected, kRelativeTolerance * expected);
    EXPECT_GT(expectedClamped, 250u);  // the random partly-outside ones and the two outside
    EXPECT_EQ(grid.clampedSegments, expectedClamped);
    for (float d : grid.density) ASSERT_GE(d, 0.0f);
}

TEST(VoxelDensity, SegmentsEntirelyOutsideDepositNothingAndAreCounted) {
    DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
    voxelizeLines(makeLines({{gridPoint(grid, {-1, 2, 2}), gridPoint(grid, {-3, 5, 5}), 0.1f, 0.1f, 1, 1},
                             {gridPoint(grid, {5, 5, 14}), gridPoint(grid, {5, 5, 14}), 0.1f, 0.1f, 1, 1}}),
                  grid);
    EXPECT_EQ(grid.total(), 0.0);
    EXPECT_EQ(grid.clampedSegments, 2u);
}

TEST(VoxelDensity, PartlyOutsideSegmentDepositsTheAnalyticVolumeOfItsClippedPart) {
    DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
    // Along x from grid coordinate -4 to 6 at a voxel centre: the part in [0, 6] is deposited.
    const Segment s{gridPoint(grid, {-4, 3.5f, 4.5f}), gridPoint(grid, {6, 3.5f, 4.5f}), 0.01f, 0.03f, 0.2f, 0.9f};
    voxelizeLines(makeLines({s}), grid);
    const double expected = analyticDensity(s, 0.4, 1.0, grid.voxelSize);
    EXPECT_NEAR(grid.total(), expected, kRelativeTolerance * expected);
    EXPECT_EQ(grid.clampedSegments, 1u);
    EXPECT_EQ(nonZeroVoxels(grid), 6u);
}

TEST(VoxelDensity, SegmentInsideOneVoxelDepositsOnlyThereTheTruncatedConeVolume) {
    DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
    const Segment s{
        gridPoint(grid, {5.1f, 3.2f, 7.3f}), gridPoint(grid, {5.8f, 3.9f, 7.7f}), 0.004f, 0.011f, 0.6f, 0.6f};
    voxelizeLines(makeLines({s}), grid);
    // pi l (ra^2 + ra rb + rb^2) / 3, times the opacity, in voxel volumes.
    const double l = glm::length(glm::dvec3(s.b) - glm::dvec3(s.a));
    const double ra = s.ra, rb = s.rb, h = grid.voxelSize;
    const double expected = 0.6 * kPi * l * (ra * ra + ra * rb + rb * rb) / 3.0 / (h * h * h);
    EXPECT_NEAR(grid.density[grid.index(5, 3, 7)], expected, kRelativeTolerance * expected);
    EXPECT_EQ(nonZeroVoxels(grid), 1u);
    EXPECT_EQ(grid.clampedSegments, 0u);
}

TEST(VoxelDensity, LongAxisAlignedSegmentDepositsEqualAmountsPerVoxelAlongItsPath) {
    DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
    // From face x = 2 to face x = 14, at a voxel centre in y and z.
    const float r = 0.02f, alpha = 0.7f;
    voxelizeLines(
        makeLines({{gridPoint(grid, {2, 4.5f, 6.5f}), gridPoint(grid, {14, 4.5f, 6.5f}), r, r, alpha, alpha}}), grid);
    const double h = grid.voxelSize;
    const double perVoxel = alpha * kPi * double(r) * r * h / (h * h * h);
    for (int x = 0; x < grid.size.x; ++x) {
        const float d = grid.density[grid.index(x, 4, 6)];
        if (x >= 2 && x < 14)
            EXPECT_NEAR(d, perVoxel, kRelativeTolerance * perVoxel) << x;
        else
            EXPECT_EQ(d, 0.0f) << x;
    }
    EXPECT_EQ(nonZeroVoxels(grid), 12u);
}

TEST(VoxelDensity, OpacityRampDepositsTheMeanOpacityOfEachVoxelPiece) {
    DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
    // Opacity 0 -> 1 over 10 voxels: voxel i holds the tube times the mean opacity (i + 0.5) / 10.
    const float r = 0.01f;
    voxelizeLines(makeLines({{gridPoint(grid, {3, 2.5f, 2.5f}), gridPoint(grid, {13, 2.5f, 2.5f}), r, r, 0.0f, 1.0f}}),
                  grid);
    const double h = grid.voxelSize;
    for (int i = 0; i < 10; ++i) {
        const double expected = (i + 0.5) / 10.0 * kPi * double(r) * r / (h * h);
        EXPECT_NEAR(grid.density[grid.index(3 + i, 2, 2)], expected, kRelativeTolerance * expected) << i;
    }
}

TEST(VoxelDensity, AxisOnAFaceOrEdgeDepositsIntoTheVoxelsWithTheLargerIndexInEitherDirection) {
    for (bool reversed : {false, true}) {
        DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
        // Along x on the edge y = 3, z = 5 (both faces), between faces x = 4 and x = 10.
        glm::vec3 a = gridPoint(grid, {4, 3, 5}), b = gridPoint(grid, {10, 3, 5});
        if (reversed) std::swap(a, b);
        // And along y on the face x = 12 (z at a centre).
        glm::vec3 c = gridPoint(grid, {12, 1, 8.5f}), e = gridPoint(grid, {12, 7, 8.5f});
        if (reversed) std::swap(c, e);
        voxelizeLines(makeLines({{a, b, 0.01f, 0.01f, 1, 1}, {c, e, 0.01f, 0.01f, 1, 1}}), grid);
        for (int x = 4; x < 10; ++x) EXPECT_GT(grid.density[grid.index(x, 3, 5)], 0.0f) << x << " " << reversed;
        for (int y = 1; y < 7; ++y) EXPECT_GT(grid.density[grid.index(12, y, 8)], 0.0f) << y << " " << reversed;
        EXPECT_EQ(nonZeroVoxels(grid), 12u) << reversed;
    }
}

TEST(VoxelDensity, SampleInterpolatesTrilinearlyBetweenVoxelCentresAndIsZeroOutside) {
    DensityGrid grid = makeDensityGrid(testBounds(), kTestResolution);
    grid.density[grid.index(4, 5, 6)] = 2.0f;
    const glm::vec3 centre = gridPoint(grid, {4.5f, 5.5f, 6.5f});
    EXPECT_FLOAT_EQ(grid.sample(centre), 2.0f);
    EXPECT_FLOAT_EQ(grid.sample(centre + glm::vec3(0.5f, 0, 0) * grid.voxelSize), 1.0f);
    EXPECT_FLOAT_EQ(grid.sample(centre + glm::vec3(0.5f, -0.5f, 0.5f) * grid.voxelSize), 0.25f);
    EXPECT_FLOAT_EQ(grid.sample(centre + glm::vec3(1.0f, 0, 0) * grid.voxelSize), 0.0f);
    EXPECT_EQ(grid.total(), 2.0);

    // Outside the grid: the zero border, fading in over the outer half voxel.
    grid.density[grid.index(0, 0, 0)] = 4.0f;
    EXPECT_FLOAT_EQ(grid.sample(gridPoint(grid, {0.5f, 0.5f, 0.5f})), 4.0f);
    EXPECT_FLOAT_EQ(grid.sample(gridPoint(grid, {0.0f, 0.5f, 0.5f})), 2.0f);
    EXPECT_EQ(grid.sample(gridPoint(grid, {-3.0f, 0.5f, 0.5f})), 0.0f);
}

TEST(VoxelDensity, GridIsBitIdenticalForOneTwoAndFourThreadsAndAnySegmentOrder) {
    StyleSpec style;
    style.radius.constant = 0.01f;
    style.opacity.constant = 0.3f;
    StyledLines lines = styleLines(generateTornado(400, 200, 7), style, "test");
    // Opacity varying along the lines, so deposits are not all alike.
    for (std::size_t i = 0; i < lines.color.size(); ++i) lines.color[i].w = float(i % 17) / 16.0f;

    std::vector<DensityGrid> grids;
    for (int threads : {1, 2, 4}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        grids.push_back(makeDensityGrid(lines.bounds, 64));
        voxelizeLines(lines, grids.back());
    }
    // Reversed segment order (what a visibility sort does to the index buffer).
    StyledLines reversed = lines;
    const std::size_t n = reversed.segmentCount();
    for (std::size_t s = 0; s < n; ++s) {
        reversed.segmentVertices[2 * s] = lines.segmentVertices[2 * (n - 1 - s)];
        reversed.segmentVertices[2 * s + 1] = lines.segmentVertices[2 * (n - 1 - s) + 1];
    }
    grids.push_back(makeDensityGrid(lines.bounds, 64));
    voxelizeLines(reversed, grids.back());

    ASSERT_GT(grids[0].total(), 0.0);
    EXPECT_EQ(grids[0].clampedSegments, 0u);  // the bounds include the radii
    for (std::size_t i = 1; i < grids.size(); ++i) {
        EXPECT_EQ(grids[i].size, grids[0].size) << i;
        EXPECT_TRUE(grids[i].density == grids[0].density) << "grid " << i << " differs";
    }
}
