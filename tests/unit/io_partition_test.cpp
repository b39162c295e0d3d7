// Partitioned line sets (io/partition.h): the whole load gives back the source exactly (same
// polylines in the same order, same vertices and attribute values) although segments near
// boundaries are stored in several bricks; a region load is that region's extracted line set;
// broken sets are input errors naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "core/error.h"
#include "core/generators.h"
#include "core/kd_decomposition.h"
#include "core/tangent_frame.h"
#include "io/dataset.h"
#include "io/json_file.h"
#include "io/partition.h"
#include "test_tmp.h"

namespace tc {
namespace {

namespace fs = std::filesystem;

void expectSameLines(const LineSet& a, const LineSet& b) {
    ASSERT_EQ(a.offsets, b.offsets);
    ASSERT_EQ(a.positions, b.positions);
    ASSERT_EQ(a.attributes.size(), b.attributes.size());
    for (std::size_t i = 0; i < a.attributes.size(); ++i) {
        EXPECT_EQ(a.attributes[i].name, b.attributes[i].name);
        EXPECT_EQ(a.attributes[i].values, b.attributes[i].values) << a.attributes[i].name;
        EXPECT_EQ(a.attributes[i].min, b.attributes[i].min) << a.attributes[i].name;
        EXPECT_EQ(a.attributes[i].max, b.attributes[i].max) << a.attributes[i].name;
    }
    EXPECT_EQ(a.velocity, b.velocity);
    EXPECT_EQ(a.bounds.lo, b.bounds.lo);
    EXPECT_EQ(a.bounds.hi, b.bounds.hi);
}

// Thick tubes, so that many segments cross region boundaries and are stored more than once.
constexpr float kRadius = 0.05f;

PartitionIndex partition(const LineSet& lines, int regions, const std::string& dir) {
    return writePartition(lines, KdDecomposition::build(segmentMidpoints(lines), regions), kRadius, "test", dir);
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(Partition, whole_load_is_the_source_line_set_exactly) {
    const LineSet lines = generateDataset("tornado", 60, 120, 5);
    ASSERT_FALSE(lines.attributes.empty());
    for (int n : {1, 2, 3, 7}) {
        const std::string dir = test::testDir() + "/n" + std::to_string(n);
        fs::create_directories(dir);
        const PartitionIndex written = partition(lines, n, dir);
        std::uint64_t stored = 0, owned = 0;
        for (const PartitionBrick& b : written.bricks) {
            stored += b.segments;
            owned += b.ownedSegments;
        }
        EXPECT_EQ(owned, lines.segmentCount());
        if (n > 1) {
            EXPECT_GT(stored, lines.segmentCount() + 100) << "few duplicates: the test checks little";
        }
        // The directory, its index.json, and through loadDataset as a scene's dataset.path.
        for (const std::string& path : {dir, dir + "/index.json"}) {
            ASSERT_TRUE(isPartitionPath(path));
            expectSameLines(readPartitionWhole(readPartitionIndex(path)), lines);
            DatasetSpec spec;
            spec.path = path;
            EXPECT_TRUE(isDatasetFile(path));
            expectSameLines(loadDataset(spec).lines, lines);
        }
    }
}

// A rank that holds a run of a polyline carries the rotation-minimising frame along it from the
// tangent stored with the run (runs version 2), and must get the frame one process carrying it
// from the polyline's start gets, bit for bit (the AO line cache's azimuths).
TEST(Partition, runs_carry_the_frame_of_the_whole_polyline) {
    const LineSet lines = generateDataset("tornado", 30, 80, 4);
    const std::vector<glm::vec3> whole = transportedTangents(lines);
    const std::string dir = test::testDir();
    const PartitionIndex index = partition(lines, 3, dir);
    std::size_t cut = 0, segments = 0;
    for (int k = 0; k < 3; ++k) {
        std::vector<RunOrigin> origins;
        std::vector<glm::vec3> tangents;
        const LineSet brick = readPartitionRegion(index, k, &origins, &tangents);
        ASSERT_EQ(tangents.size(), brick.polylineCount());
        EXPECT_EQ(tangents, incomingTangents(lines, whole, origins));
        for (std::size_t q = 0; q < brick.polylineCount(); ++q) {
            const RunOrigin& o = origins[q];
            const bool starts = o.firstVertex == lines.offsets[o.polyline];
            EXPECT_EQ(tangents[q] == glm::vec3(0.0f), starts) << "region " << k << ", run " << q;
            cut += !starts;
            glm::vec3 carried = tangents[q];
            for (std::uint32_t v = brick.offsets[q]; v + 1 < brick.offsets[q + 1]; ++v, ++segments) {
                const glm::vec3 axis = segmentAxis(brick.positions[v], brick.positions[v + 1]);
                glm::vec3 t, b;
                tangentFrame(axis, t, b);
                carried = transportTangent(carried, axis, t);
                const std::uint64_t g = o.firstVertex + (v - brick.offsets[q]);  // the source's vertex
                ASSERT_EQ(carried, whole[g - o.polyline]) << "region " << k << ", run " << q << ", vertex " << g;
            }
        }
    }
    EXPECT_GT(cut, 20u) << "few runs start inside a polyline: the test checks little";
    EXPECT_GT(segments, lines.segmentCount());
}

TEST(Partition, index_round_trips_the_tree_boxes_and_counts) {
    const LineSet lines = generateDataset("propeller", 20, 50, 2);
    const std::string dir = test::testDir();
    const PartitionIndex written = partition(lines, 5, dir);
    const PartitionIndex read = readPartitionIndex(dir);
    EXPECT_TRUE(read.tree == written.tree);
    EXPECT_EQ(read.radius, kRadius);
    EXPECT_EQ(read.source, "test");
    EXPECT_EQ(read.polylines, lines.polylineCount());
    EXPECT_EQ(read.vertices, lines.vertexCount());
    EXPECT_EQ(read.bounds.lo, lines.bounds.lo);
    EXPECT_EQ(read.bounds.hi, lines.bounds.hi);
    ASSERT_EQ(read.bricks.size(), 5u);
    for (int k = 0; k < 5; ++k) {
        const PartitionBrick &a = read.bricks[std::size_t(k)], &b = written.bricks[std::size_t(k)];
        EXPECT_EQ(a.file, "region-" + std::to_string(k) + ".tcb");
        EXPECT_TRUE(a.box == read.tree.box(k));
        EXPECT_EQ(a.polylines, b.polylines);
        EXPECT_EQ(a.vertices, b.vertices);
        EXPECT_EQ(a.assignedSegments, b.assignedSegments);
        EXPECT_EQ(a.ownedSegments, b.ownedSegments);
    }
    ASSERT_EQ(read.attributes.size(), lines.attributes.size());
    for (std::size_t i = 0; i < lines.attributes.size(); ++i) {
        EXPECT_EQ(read.attributes[i].name, lines.attributes[i].name);
        EXPECT_EQ(read.attributes[i].min, lines.attributes[i].min);
        EXPECT_EQ(read.attributes[i].max, lines.attributes[i].max);
    }
}

TEST(Partition, region_load_is_the_assigned_subset_with_its_joint_neighbours) {
    const LineSet lines = generateDataset("tornado", 40, 100, 7);
    const std::string dir = test::testDir();
    const PartitionIndex index = partition(lines, 4, dir);
    const RegionItems assigned = assignSegments(index.tree, lines, kRadius);
    for (int k = 0; k < 4; ++k) {
        std::vector<RunOrigin> origins;
        const LineSet region = readPartitionRegion(index, k, &origins);
        const RegionLines expected = extractRegionLines(lines, assigned[std::size_t(k)]);
        expectSameLines(region, expected.lines);
        EXPECT_EQ(origins, expected.origins);
        // Global styling ranges, though the brick holds only part of the values.
        for (std::size_t a = 0; a < lines.attributes.size(); ++a) {
            EXPECT_EQ(region.attributes[a].min, lines.attributes[a].min);
            EXPECT_EQ(region.attributes[a].max, lines.attributes[a].max);
        }
        EXPECT_EQ(ownedSegments(index.tree, k, region).size(), index.bricks[std::size_t(k)].ownedSegments);
    }
    EXPECT_NE(errorOf([&] { readPartitionRegion(index, 4); }).find("region 4 requested, the set has 4 regions"),
              std::string::npos);
}

TEST(Partition, an_empty_line_set_partitions_and_loads_empty) {
    const std::string dir = test::testDir();
    const LineSet empty;
    partition(empty, 3, dir);
    const LineSet back = readPartitionWhole(readPartitionIndex(dir));
    EXPECT_EQ(back.polylineCount(), 0u);
    EXPECT_EQ(back.vertexCount(), 0u);
}

class BrokenPartition : public ::testing::Test {
protected:
    void SetUp() override {
        dir = test::testDir();
        partition(generateDataset("tornado", 20, 60, 3), 3, dir);
        index = readJsonFile(dir + "/index.json");
    }
    void save() { writeJsonFile(dir + "/index.json", index); }
    std::string wholeError() {
        return errorOf([&] { readPartitionWhole(readPartitionIndex(dir)); });
    }
    std::string dir;
    nlohmann::json index;
};

TEST_F(BrokenPartition, a_missing_brick_names_the_file_and_its_index) {
    fs::remove(dir + "/region-1.tcb");
    const std::string e = wholeError();
    EXPECT_NE(e.find(dir + "/region-1.tcb: no such file (region 1 of " + dir + "/index.json)"), std::string::npos) << e;
}

TEST_F(BrokenPartition, a_missing_runs_file_fails_the_whole_load_but_not_the_region_load) {
    fs::remove(dir + "/region-2.runs");
    const std::string e = wholeError();
    EXPECT_NE(e.find(dir + "/region-2.runs: no such file"), std::string::npos) << e;
    EXPECT_NO_THROW(readPartitionRegion(readPartitionIndex(dir), 2));
}

TEST_F(BrokenPartition, another_version_is_refused) {
    index["version"] = 2;
    save();
    const std::string e = wholeError();
    EXPECT_NE(e.find(dir + "/index.json: version: unsupported partition version 2 (this build reads version 1)"),
              std::string::npos)
        << e;
}

TEST_F(BrokenPartition, a_brick_count_that_disagrees_with_the_file_is_refused) {
    index["regions"][0]["vertices"] = index["regions"][0]["vertices"].get<std::uint64_t>() + 1;
    index["regions"][0]["segments"] = index["regions"][0]["segments"].get<std::uint64_t>() + 1;
    save();
    const std::string e = wholeError();
    EXPECT_NE(e.find(dir + "/region-0.tcb: "), std::string::npos) << e;
    EXPECT_NE(e.find("vertices, " + dir + "/index.json says"), std::string::npos) << e;
}

TEST_F(BrokenPartition, owned_counts_that_do_not_add_up_are_refused) {
    index["counts"]["segments"] = index["counts"]["segments"].get<std::uint64_t>() + 1;
    index["counts"]["vertices"] = index["counts"]["vertices"].get<std::uint64_t>() + 1;
    save();
    const std::string e = wholeError();
    EXPECT_NE(e.find(dir + "/index.json: regions: the regions own"), std::string::npos) << e;
}

TEST_F(BrokenPartition, a_box_that_is_not_the_trees_is_refused) {
    index["regions"][1]["box"]["lo"][0] = 123.0;
    save();
    const std::string e = wholeError();
    EXPECT_NE(e.find(dir + "/index.json: regions[1].box: does not match region 1 of the tree"), std::string::npos) << e;
}

TEST_F(BrokenPartition, a_truncated_runs_file_names_it) {
    fs::resize_file(dir + "/region-0.runs", fs::file_size(dir + "/region-0.runs") - 8);
    const std::string e = wholeError();
    EXPECT_NE(e.find(dir + "/region-0.runs: byte"), std::string::npos) << e;
}

TEST(Partition, scenes_and_other_json_files_are_not_partitions) {
    const std::string dir = test::testDir();
    writeJsonFile(dir + "/scene.json", {{"dataset", {{"generate", "tornado"}}}});
    EXPECT_FALSE(isPartitionPath(dir + "/scene.json"));
    EXPECT_FALSE(isPartitionPath(dir));  // no index.json in it
    EXPECT_FALSE(isPartitionPath(dir + "/missing.json"));
    EXPECT_FALSE(isPartitionPath(""));
    EXPECT_NE(errorOf([&] { readPartitionIndex(dir); }).find(dir + ": no index.json"), std::string::npos);
    EXPECT_NE(errorOf([&] { readPartitionIndex(dir + "/scene.json"); }).find("scene.json: format:"), std::string::npos);
}

}  // namespace
}  // namespace tc
