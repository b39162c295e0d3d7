#include "core/line_set.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace tc {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// One polyline per entry; attribute "s" = 10 * input vertex index, to see which vertices survive.
LineSet makeLines(const std::vector<std::vector<glm::vec3>>& polylines) {
    LineSet lines;
    for (const auto& pl : polylines) {
        for (const glm::vec3& p : pl) lines.positions.push_back(p);
        lines.offsets.push_back(std::uint32_t(lines.positions.size()));
    }
    Attribute s{"s", {}};
    for (std::size_t i = 0; i < lines.positions.size(); ++i) s.values.push_back(10.0f * float(i));
    lines.attributes.push_back(s);
    return lines;
}

TEST(CleanLineSet, nan_in_the_middle_splits_the_polyline) {
    LineSet lines = makeLines({{{0, 0, 0}, {1, 0, 0}, {kNaN, 0, 0}, {2, 0, 0}, {3, 0, 0}}});
    CleanReport r = cleanLineSet(lines);
    EXPECT_EQ(r.nonFiniteVertices, 1u);
    EXPECT_EQ(r.duplicateVertices, 0u);
    EXPECT_EQ(r.droppedPolylines, 0u);
    ASSERT_EQ(lines.polylineCount(), 2u);
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 2, 4}));
    EXPECT_EQ(lines.positions[2], glm::vec3(2, 0, 0));
    EXPECT_EQ(lines.attributes[0].values, (std::vector<float>{0, 10, 30, 40}));
}

TEST(CleanLineSet, inf_splits_and_one_vertex_pieces_are_dropped) {
    // Inf after the first vertex leaves a 1-vertex piece, which is dropped.
    LineSet lines = makeLines({{{0, 0, 0}, {0, kInf, 0}, {2, 0, 0}, {3, 0, 0}}});
    CleanReport r = cleanLineSet(lines);
    EXPECT_EQ(r.nonFiniteVertices, 1u);
    EXPECT_EQ(r.droppedPolylines, 1u);
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 2}));
    EXPECT_EQ(lines.attributes[0].values, (std::vector<float>{20, 30}));
}

TEST(CleanLineSet, consecutive_duplicates_are_removed) {
    LineSet lines = makeLines({{{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 0, 0}}});
    CleanReport r = cleanLineSet(lines);
    EXPECT_EQ(r.duplicateVertices, 3u);
    EXPECT_EQ(r.nonFiniteVertices, 0u);
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 3}));
    // The first of each run of duplicates is kept; non-consecutive repeats (a closed loop) stay.
    EXPECT_EQ(lines.attributes[0].values, (std::vector<float>{0, 20, 50}));
}

TEST(CleanLineSet, short_and_degenerate_polylines_are_dropped) {
    LineSet lines = makeLines({
        {{0, 0, 0}},                   // 1 vertex
        {{5, 5, 5}, {5, 5, 5}},        // collapses to 1 vertex
        {},                            // empty
        {{kNaN, 0, 0}, {0, kNaN, 0}},  // nothing finite
        {{1, 1, 1}, {2, 2, 2}},        // kept
    });
    CleanReport r = cleanLineSet(lines);
    EXPECT_EQ(r.droppedPolylines, 4u);
    EXPECT_EQ(r.duplicateVertices, 1u);
    EXPECT_EQ(r.nonFiniteVertices, 2u);
    ASSERT_EQ(lines.polylineCount(), 1u);
    EXPECT_EQ(lines.positions, (std::vector<glm::vec3>{{1, 1, 1}, {2, 2, 2}}));
    EXPECT_EQ(lines.attributes[0].values.size(), 2u);
    EXPECT_EQ(r.summary(),
              "skipped 2 non-finite vertices (polylines split there), 1 duplicate vertex "
              "(zero-length segments), 4 polylines with fewer than 2 vertices");
}

TEST(CleanLineSet, bounds_and_attribute_ranges_are_recomputed) {
    LineSet lines = makeLines({{{-1, 0, 0}, {kNaN, 9, 9}, {1, 2, 3}, {4, -5, 6}}});
    lines.attributes[0].values[3] = kNaN;  // a NaN attribute value does not affect the range
    lines.bounds.extend({100, 100, 100});
    CleanReport r = cleanLineSet(lines);
    EXPECT_EQ(r.droppedPolylines, 1u);  // {-1,0,0} alone before the NaN
    EXPECT_EQ(lines.bounds.lo, glm::vec3(1, -5, 3));
    EXPECT_EQ(lines.bounds.hi, glm::vec3(4, 2, 6));
    EXPECT_EQ(lines.attributes[0].min, 20.0f);
    EXPECT_EQ(lines.attributes[0].max, 20.0f);
}

TEST(CleanLineSet, clean_input_reports_nothing) {
    LineSet lines = makeLines({{{0, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {0, 2, 0}, {0, 3, 0}}});
    CleanReport r = cleanLineSet(lines);
    EXPECT_FALSE(r.any());
    EXPECT_EQ(r.summary(), "");
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 2, 5}));
}

TEST(Attribute, range_of_finite_values_and_nan_when_none) {
    Attribute a{"a", {kNaN, 3.0f, -kInf, -2.0f}};
    a.updateRange();
    EXPECT_EQ(a.min, -2.0f);
    EXPECT_EQ(a.max, 3.0f);
    Attribute b{"b", {kNaN}};
    b.updateRange();
    EXPECT_TRUE(std::isnan(b.min));
    EXPECT_TRUE(std::isnan(b.max));
}

// Large enough that the parallel scan and reductions split into many chunks: a clean set comes
// back unchanged with exact bounds and ranges, and one defect in any polyline (first, middle,
// last) still sends it through the compaction.
TEST(CleanLineSet, clean_sets_are_left_alone_and_a_single_defect_anywhere_is_found) {
    std::vector<std::vector<glm::vec3>> polylines(3000);
    for (std::size_t p = 0; p < polylines.size(); ++p)
        for (int v = 0; v < 50; ++v)
            polylines[p].push_back({float(p) * 0.5f, std::sin(0.1f * float(v + p)), float(v) - 7.0f});
    LineSet clean = makeLines(polylines);
    const LineSet before = clean;
    EXPECT_FALSE(cleanLineSet(clean).any());
    EXPECT_EQ(clean.positions, before.positions);
    EXPECT_EQ(clean.offsets, before.offsets);
    EXPECT_EQ(clean.attributes[0].values, before.attributes[0].values);
    Bounds serial;
    for (const glm::vec3& p : before.positions) serial.extend(p);
    EXPECT_EQ(clean.bounds.lo, serial.lo);
    EXPECT_EQ(clean.bounds.hi, serial.hi);
    EXPECT_EQ(clean.attributes[0].min, 0.0f);
    EXPECT_EQ(clean.attributes[0].max, 10.0f * float(before.positions.size() - 1));

    for (std::size_t p : {std::size_t(0), polylines.size() / 2, polylines.size() - 1}) {
        LineSet duplicate = before;
        std::size_t v = duplicate.offsets[p] + 20;
        duplicate.positions[v] = duplicate.positions[v - 1];
        EXPECT_EQ(cleanLineSet(duplicate).duplicateVertices, 1u) << "polyline " << p;
        LineSet nonFinite = before;
        nonFinite.positions[nonFinite.offsets[p + 1] - 1].y = kNaN;
        EXPECT_EQ(cleanLineSet(nonFinite).nonFiniteVertices, 1u) << "polyline " << p;
    }
}

TEST(LineSet, attribute_lookup_by_name) {
    LineSet lines = makeLines({{{0, 0, 0}, {1, 0, 0}}});
    ASSERT_NE(lines.attribute("s"), nullptr);
    EXPECT_EQ(lines.attribute("s")->name, "s");
    EXPECT_EQ(lines.attribute("missing"), nullptr);
}

}  // namespace
}  // namespace tc
