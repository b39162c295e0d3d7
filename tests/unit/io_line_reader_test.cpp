#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/particle_generators.h"
#include "io/line_reader.h"
#include "test_tmp.h"

namespace fs = std::filesystem;

namespace tc {
namespace {

using tc::test::testDir;  // a fresh directory per test (test_tmp.h)

std::string writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

// Runs `f`, expects an InputError, returns its message, and checks VTK printed nothing.
template <class F>
std::string inputErrorOf(F&& f) {
    ::testing::internal::CaptureStderr();
    std::string message;
    try {
        f();
        ADD_FAILURE() << "no InputError thrown";
    } catch (const InputError& e) {
        message = e.what();
    }
    std::string spilled = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(spilled, "") << "VTK output reached stderr";
    return message;
}

const char* const kLegacyAscii = R"(# vtk DataFile Version 3.0
two polylines
ASCII
DATASET POLYDATA
POINTS 5 float
0 0 0
1 0 0
2 0 0
0 1 0
0 2 0
VERTICES 1 2
1 0
LINES 2 7
3 0 1 2
2 4 3
POINT_DATA 5
SCALARS temperature float 1
LOOKUP_TABLE default
1 2 3 4 5
VECTORS velocity float
3 4 0
0 0 1
1 0 0
0 2 0
0 0 0
)";

TEST(ReadLineSet, legacy_ascii_polydata_with_scalars_and_vectors) {
    std::string path = writeText(testDir() + "/lines.vtk", kLegacyAscii);
    CleanReport report;
    LineSet lines = readLineSet(path, &report);
    EXPECT_FALSE(report.any());
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 3, 5}));
    EXPECT_EQ(lines.positions, (std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 1, 0}}));
    ASSERT_EQ(lines.attributes.size(), 5u);
    auto values = [&](const char* name) {
        const Attribute* a = lines.attribute(name);
        EXPECT_NE(a, nullptr) << name;
        return a ? a->values : std::vector<float>{};
    };
    // Per vertex, following the cells' point ids (the second polyline runs 4 -> 3).
    EXPECT_EQ(values("temperature"), (std::vector<float>{1, 2, 3, 5, 4}));
    EXPECT_EQ(values("velocity_x"), (std::vector<float>{3, 0, 1, 0, 0}));
    EXPECT_EQ(values("velocity_y"), (std::vector<float>{4, 0, 0, 0, 2}));
    EXPECT_EQ(values("velocity_z"), (std::vector<float>{0, 1, 0, 0, 0}));
    EXPECT_EQ(values("velocity_magnitude"), (std::vector<float>{5, 1, 1, 0, 2}));
    EXPECT_EQ(lines.attribute("velocity_magnitude")->max, 5.0f);
    EXPECT_EQ(lines.bounds.hi, glm::vec3(2, 2, 0));
}

// Legacy binary is big-endian.
template <class T>
void putBigEndian(std::string& out, T value) {
    static_assert(sizeof(T) == 4);
    std::uint32_t bits;
    std::memcpy(&bits, &value, 4);
    for (int shift = 24; shift >= 0; shift -= 8) out += char((bits >> shift) & 0xFF);
}

TEST(ReadLineSet, legacy_binary_with_a_nan_coordinate_reports_one_non_finite_vertex) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::string text = "# vtk DataFile Version 3.0\nnan\nBINARY\nDATASET POLYDATA\nPOINTS 5 float\n";
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 2.f, nan, 0.f, 3.f, 0.f, 0.f, 4.f, 0.f, 0.f}) putBigEndian(text, v);
    text += "\nLINES 1 6\n";
    for (std::int32_t v : {5, 0, 1, 2, 3, 4}) putBigEndian(text, v);
    text += "\n";
    std::string path = writeText(testDir() + "/nan.vtk", text);

    CleanReport report;
    LineSet lines = readLineSet(path, &report);
    EXPECT_EQ(report.nonFiniteVertices, 1u);
    EXPECT_EQ(report.droppedPolylines, 0u);
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 2, 4}));
    EXPECT_EQ(lines.positions[2], glm::vec3(3, 0, 0));
}

TEST(ReadLineSet, legacy_unstructured_grid_takes_line_and_polyline_cells) {
    std::string path = writeText(testDir() + "/grid.vtk", R"(# vtk DataFile Version 3.0
grid
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 4 float
0 0 0  1 0 0  1 1 0  0 1 0
CELLS 3 12
3 0 1 2
3 1 2 3
2 3 0
CELL_TYPES 3
4
5
3
)");
    LineSet lines = readLineSet(path);
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 3, 5}));  // the triangle is skipped
    EXPECT_EQ(lines.positions[3], glm::vec3(0, 1, 0));
}

TEST(ReadLineSet, vtp_round_trip_keeps_positions_offsets_and_attributes) {
    LineSet lines;
    lines.positions = {{0, 0, 0}, {1, 0.5f, 0}, {2, 0, 1e-3f}, {-1, -1, -1}, {-2, -1, -1}};
    lines.offsets = {0, 3, 5};
    lines.attributes = {{"speed", {0.1f, 0.2f, 0.3f, 0.4f, 0.5f}}, {"v_x", {1, 2, 3, 4, -5}}};
    std::string path = testDir() + "/round.vtp";
    writeLineSetVtp(lines, path);

    LineSet back = readLineSet(path);
    EXPECT_EQ(back.positions, lines.positions);
    EXPECT_EQ(back.offsets, lines.offsets);
    ASSERT_EQ(back.attributes.size(), 2u);
    for (const Attribute& a : lines.attributes) {
        ASSERT_NE(back.attribute(a.name), nullptr) << a.name;
        EXPECT_EQ(back.attribute(a.name)->values, a.values) << a.name;
    }
    EXPECT_EQ(back.attribute("v_x")->min, -5.0f);

    std::ifstream in(path, std::ios::binary);
    std::string file(std::istreambuf_iterator<char>(in), {});
    EXPECT_NE(file.find("format=\"appended\""), std::string::npos);
    EXPECT_NE(file.find("<AppendedData encoding=\"raw\">"), std::string::npos);
    // No temp file left next to it.
    EXPECT_EQ(std::distance(fs::directory_iterator(fs::path(path).parent_path()), fs::directory_iterator{}), 1);
}

// A ParaView partitioned PolyData file (.pvtp) naming `pieces` (.vtp files next to it) with one
// float point array "speed".
std::string writePvtp(const std::string& path, const std::vector<std::string>& pieces) {
    std::string text = R"(<?xml version="1.0"?>
<VTKFile type="PPolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <PPolyData GhostLevel="0">
    <PPointData><PDataArray type="Float32" Name="speed"/></PPointData>
    <PPoints><PDataArray type="Float32" Name="Points" NumberOfComponents="3"/></PPoints>
)";
    for (const std::string& p : pieces) text += "    <Piece Source=\"" + p + "\"/>\n";
    return writeText(path, text + "  </PPolyData>\n</VTKFile>\n");
}

// Two pieces: polylines {0..2}, {3..4} and {5..7}, {8..9}; speed = 10 x vertex index.
std::string writeTwoPieces(const std::string& dir) {
    for (int piece = 0; piece < 2; ++piece) {
        LineSet lines;
        lines.offsets = {0, 3, 5};
        std::vector<float> speed;
        for (int v = 0; v < 5; ++v) {
            lines.positions.emplace_back(float(5 * piece + v), float(v * v), float(piece));
            speed.push_back(float(10 * (5 * piece + v)));
        }
        lines.attributes = {{"speed", speed}};
        writeLineSetVtp(lines, dir + "/piece" + std::to_string(piece) + ".vtp");
    }
    return writePvtp(dir + "/lines.pvtp", {"piece0.vtp", "piece1.vtp"});
}

TEST(ReadLineSet, pvtp_is_read_as_its_pieces_in_file_order) {
    const std::string path = writeTwoPieces(testDir());
    EXPECT_TRUE(isVtkFile(path));
    EXPECT_TRUE(isPiecedVtkFile(path));
    EXPECT_FALSE(isPiecedVtkFile("lines.vtp"));
    const LineSet whole = readLineSet(path);
    EXPECT_EQ(whole.offsets, (std::vector<std::uint32_t>{0, 3, 5, 8, 10}));
    ASSERT_EQ(whole.positions.size(), 10u);
    for (int v = 0; v < 10; ++v) {
        const int piece = v / 5, local = v % 5;
        EXPECT_EQ(whole.positions[std::size_t(v)], glm::vec3(float(v), float(local * local), float(piece))) << v;
    }
    ASSERT_NE(whole.attribute("speed"), nullptr);
    EXPECT_EQ(whole.attribute("speed")->values, (std::vector<float>{0, 10, 20, 30, 40, 50, 60, 70, 80, 90}));
    EXPECT_EQ(whole.attribute("speed")->max, 90.0f);
}

TEST(ReadLineSet, pvtp_shares_hold_contiguous_pieces) {
    const std::string path = writeTwoPieces(testDir());
    const LineSet first = readLinePieces(path, 0, 2), second = readLinePieces(path, 1, 2);
    EXPECT_EQ(first.offsets, (std::vector<std::uint32_t>{0, 3, 5}));
    EXPECT_EQ(second.offsets, (std::vector<std::uint32_t>{0, 3, 5}));
    EXPECT_EQ(first.positions[4], glm::vec3(4, 16, 0));
    EXPECT_EQ(second.positions[0], glm::vec3(5, 0, 1));
    EXPECT_EQ(second.attribute("speed")->min, 50.0f);  // the share's range
    EXPECT_EQ(readLinePieces(path, 0, 1).polylineCount(), 4u);
    // Three shares of two pieces: one share gets none, the others a piece each, in file order.
    std::vector<glm::vec3> firsts;
    for (int share = 0; share < 3; ++share) {
        const LineSet lines = readLinePieces(path, share, 3);
        EXPECT_TRUE(lines.polylineCount() == 0 || lines.polylineCount() == 2) << share;
        if (lines.polylineCount()) firsts.push_back(lines.positions.front());
    }
    EXPECT_EQ(firsts, (std::vector<glm::vec3>{{0, 0, 0}, {5, 0, 1}}));
}

TEST(ReadLineSet, pvtp_with_a_missing_piece_names_the_file) {
    const std::string dir = testDir();
    const std::string path = writeTwoPieces(dir);
    fs::remove(dir + "/piece1.vtp");
    const std::string message = inputErrorOf([&] { readLineSet(path); });
    EXPECT_EQ(message.rfind(path + ": VTK: ", 0), 0u) << message;
}

TEST(ReadLineSet, nan_written_to_vtp_is_reported_on_read) {
    LineSet lines;
    lines.positions = {{0, 0, 0}, {1, 0, 0}, {std::nanf(""), 0, 0}, {3, 0, 0}, {4, 0, 0}};
    lines.offsets = {0, 5};
    std::string path = testDir() + "/nan.vtp";
    writeLineSetVtp(lines, path);
    CleanReport report;
    LineSet back = readLineSet(path, &report);
    EXPECT_EQ(report.nonFiniteVertices, 1u);
    EXPECT_EQ(back.polylineCount(), 2u);
}

TEST(ReadLineSet, missing_file) {
    std::string path = testDir() + "/absent.vtk";
    EXPECT_EQ(inputErrorOf([&] { readLineSet(path); }), path + ": no such file");
}

TEST(ReadLineSet, unknown_extension_lists_supported_ones) {
    std::string path = writeText(testDir() + "/lines.xyz", "1 2 3\n");
    EXPECT_EQ(inputErrorOf([&] { readLineSet(path); }),
              path + ": unsupported file extension '.xyz' (supported: .vtk, .vtp, .vtu, .trk, .tck, .obj, .tcb)");
}

TEST(ReadLineSet, garbage_legacy_file_names_the_file) {
    std::string path = writeText(testDir() + "/garbage.vtk", "this is not a VTK file\n\x01\x02\x03");
    EXPECT_EQ(inputErrorOf([&] { readLineSet(path); }), path + ": VTK: Unrecognized file type: this is not a VTK file");
}

TEST(ReadLineSet, garbage_xml_file_names_the_file) {
    std::string path = writeText(testDir() + "/garbage.vtp", "<VTKFile type=\"PolyData\"><oops");
    std::string message = inputErrorOf([&] { readLineSet(path); });
    EXPECT_EQ(message.rfind(path + ": VTK: ", 0), 0u) << message;
    EXPECT_NE(message.find("line 1, column 25"), std::string::npos) << message;
}

TEST(ReadLineSet, truncated_legacy_file_names_the_file) {
    std::string text = kLegacyAscii;
    std::string path = writeText(testDir() + "/cut.vtk", text.substr(0, text.find("2 0 0")));
    EXPECT_EQ(inputErrorOf([&] { readLineSet(path); }),
              path + ": VTK: Error reading ascii data. Possible mismatch of datasize with declaration.");
}

TEST(ReadLineSet, truncated_vtp_file_names_the_file) {
    LineSet lines;
    for (int i = 0; i < 1000; ++i) lines.positions.push_back({float(i), float(i * i % 7), 0});
    lines.offsets = {0, 1000};
    std::string dir = testDir();
    writeLineSetVtp(lines, dir + "/full.vtp");
    std::string full;
    {
        std::ifstream in(dir + "/full.vtp", std::ios::binary);
        full.assign(std::istreambuf_iterator<char>(in), {});
    }
    std::string path = writeText(dir + "/cut.vtp", full.substr(0, full.size() * 2 / 3));
    std::string message = inputErrorOf([&] { readLineSet(path); });
    EXPECT_EQ(message.rfind(path + ": VTK: ", 0), 0u) << message;
}

TEST(ReadLineSet, file_without_line_cells_says_what_it_has) {
    std::string path = writeText(testDir() + "/points.vtk", R"(# vtk DataFile Version 3.0
points only
ASCII
DATASET POLYDATA
POINTS 3 float
0 0 0 1 0 0 2 0 0
VERTICES 1 4
3 0 1 2
)");
    EXPECT_EQ(inputErrorOf([&] { readLineSet(path); }), path + ": no polylines (3 points, 1 cells of other types)");
}

TEST(ReadLineSet, point_id_out_of_range_names_the_cell) {
    std::string path = writeText(testDir() + "/bad_id.vtk", R"(# vtk DataFile Version 3.0
bad id
ASCII
DATASET POLYDATA
POINTS 2 float
0 0 0 1 0 0
LINES 1 3
2 0 7
)");
    std::string message = inputErrorOf([&] { readLineSet(path); });
    EXPECT_EQ(message, path + ": cell 0: point id 7 out of range (2 points)");
}

TEST(ReadLineSet, file_whose_polylines_all_degenerate) {
    std::string path = writeText(testDir() + "/flat.vtk", R"(# vtk DataFile Version 3.0
degenerate
ASCII
DATASET POLYDATA
POINTS 2 float
1 1 1 1 1 1
LINES 1 3
2 0 1
)");
    EXPECT_EQ(inputErrorOf([&] { readLineSet(path); }),
              path +
                  ": no polylines left after cleaning (skipped 1 duplicate vertex "
                  "(zero-length segments), 1 polyline with fewer than 2 vertices)");
}

// An MRtrix file ("mrtrix tracks" or "mrtrix track scalars") with the given count line and
// little-endian floats.
std::string writeMrtrix(const std::string& path, const char* magic, const std::string& count,
                        const std::vector<float>& values) {
    std::string header = std::string(magic) + "\ndatatype: Float32LE\n" + count + "file: . ";
    const std::size_t offset = header.size() + 4 + 1 + 4;  // a 4-digit offset, "\n", "END\n"
    char number[8];
    std::snprintf(number, sizeof number, "%4zu", offset);
    header += std::string(number) + "\nEND\n";
    std::ofstream out(path, std::ios::binary);
    out << header;
    out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
    return path;
}

TEST(ReadLineSet, empty_tractograms_are_empty_line_sets) {
    // The dataset (io/dataset.h) decides whether an empty one can be rendered; reading it is fine.
    const float inf = std::numeric_limits<float>::infinity();
    const std::string tck = writeMrtrix(testDir() + "/empty.tck", "mrtrix tracks", "count: 0\n", {inf, inf, inf});
    CleanReport report;
    const LineSet lines = readLineSet(tck, &report);
    EXPECT_EQ(lines.polylineCount(), 0u);
    EXPECT_EQ(lines.vertexCount(), 0u);
    EXPECT_FALSE(report.any()) << report.summary();

    // A TrackVis header without tracks (n_count 0, version 2, little-endian).
    std::string trk(1000, '\0');
    std::memcpy(trk.data(), "TRACK", 5);
    const std::int32_t version = 2, headerSize = 1000;
    std::memcpy(trk.data() + 992, &version, 4);
    std::memcpy(trk.data() + 996, &headerSize, 4);
    EXPECT_EQ(readLineSet(writeText(testDir() + "/empty.trk", trk)).polylineCount(), 0u);
}

TEST(ReadLineSet, what_a_native_reader_tolerated_reaches_the_report) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::string dir = testDir();
    const std::string tck =
        writeMrtrix(dir + "/t.tck", "mrtrix tracks", "count: 5\n",
                    {0, 0, 0, 1, 0, 0, nan, nan, nan, 0, 1, 0, 0, 2, 0, nan, nan, nan, inf, inf, inf});
    writeMrtrix(dir + "/t_fa.tsf", "mrtrix track scalars", "count: 3\n", {0.1f, 0.2f, nan, 0.3f, 0.4f, nan, inf});
    CleanReport report;
    const LineSet lines = readLineSet(tck, &report);
    EXPECT_EQ(lines.polylineCount(), 2u);
    EXPECT_EQ(lines.attribute("fa")->values, (std::vector<float>{0.1f, 0.2f, 0.3f, 0.4f}));
    EXPECT_EQ(report.warnings, (std::vector<std::string>{"line 3: count: 5 tracks declared, the data holds 2; read 2",
                                                         dir + "/t_fa.tsf: line 3: count: 3 tracks declared, the "
                                                               "data holds 2; read 2"}));
    EXPECT_TRUE(report.any());
    EXPECT_EQ(report.summary(), report.warnings[0] + "; " + report.warnings[1]);
}

// A point cloud the way ParaView saves particles: vertex cells, a radius array, unsigned-char
// RGB colours and a vector.
const char* const kPointCloud = R"(# vtk DataFile Version 3.0
three particles
ASCII
DATASET POLYDATA
POINTS 3 float
0 0 0
1 2 3
-1 0.5 2
VERTICES 3 6
1 0
1 1
1 2
POINT_DATA 3
SCALARS Radius float 1
LOOKUP_TABLE default
0.5 0.25 2
SCALARS density float 1
LOOKUP_TABLE default
7 8 9
COLOR_SCALARS rgb 3
1 0 0
0 1 0
0 0 1
VECTORS velocity float
3 4 0
0 0 1
1 0 0
)";

TEST(ReadVtkFile, points_without_line_cells_are_particles_with_radii_colours_and_attributes) {
    const std::string path = writeText(testDir() + "/cloud.vtk", kPointCloud);
    VtkFileData data = readVtkFile(path);
    ASSERT_TRUE(data.isPoints);
    const ParticleSet& p = data.points;
    ASSERT_EQ(p.size(), 3u);
    EXPECT_EQ(p.positions[1], glm::vec3(1, 2, 3));
    EXPECT_EQ(p.radii, (std::vector<float>{0.5f, 0.25f, 2.0f}));
    ASSERT_EQ(p.colors.size(), 3u);
    // COLOR_SCALARS in a legacy file are floats in [0, 1]; VTK stores them as unsigned char.
    EXPECT_EQ(p.colors[1], glm::vec4(0, 1, 0, 1));
    ASSERT_NE(p.attribute("velocity_magnitude"), nullptr);
    EXPECT_FLOAT_EQ(p.attribute("velocity_magnitude")->values[0], 5.0f);
    EXPECT_EQ(p.attribute("Radius"), nullptr);  // taken as radii, not an attribute
    // The legacy reader drops every SCALARS section but the first unless told to read all.
    ASSERT_NE(p.attribute("density"), nullptr);
    EXPECT_EQ(p.attribute("density")->values, (std::vector<float>{7, 8, 9}));
    EXPECT_EQ(p.bounds.lo, glm::vec3(-1, 0, 0));
    EXPECT_EQ(p.bounds.hi, glm::vec3(1, 2, 3));
    // The same file through readLineSet is still an error that says what it has.
    EXPECT_NE(inputErrorOf([&] { readLineSet(path); }).find("no polylines (3 points"), std::string::npos);
}

TEST(ReadVtkFile, files_with_line_cells_are_lines_and_bad_radii_name_the_point) {
    VtkFileData lines = readVtkFile(writeText(testDir() + "/two.vtk", kLegacyAscii));
    EXPECT_FALSE(lines.isPoints);
    EXPECT_EQ(lines.lines.polylineCount(), 2u);

    std::string bad = kPointCloud;
    bad.replace(bad.find("0.5 0.25 2"), 10, "0.5 -1 2");
    const std::string path = writeText(testDir() + "/bad.vtk", bad);
    EXPECT_EQ(inputErrorOf([&] { readVtkFile(path); }),
              path + ": point 1: Radius -1.000000 (expected a positive radius)");
}

TEST(ReadVtkFile, particles_written_as_vtp_read_back_exactly) {
    ParticleSet in = generateDroplets(300, 7);
    in.colors.clear();
    for (std::size_t i = 0; i < in.size(); ++i) in.colors.push_back({float(i % 256) / 255.0f, 0.0f, 1.0f, 0.5f});
    const std::string path = testDir() + "/droplets.vtp";
    writeParticleSetVtp(in, path);
    VtkFileData out = readVtkFile(path);
    ASSERT_TRUE(out.isPoints);
    EXPECT_EQ(out.points.positions, in.positions);
    EXPECT_EQ(out.points.radii, in.radii);
    ASSERT_EQ(out.points.colors.size(), in.size());
    for (std::size_t i = 0; i < in.size(); ++i)  // 8-bit colours: exact for k/255, alpha 0.5 -> 128/255
        EXPECT_NEAR(out.points.colors[i].w, 0.5f, 0.5f / 255.0f + 1e-6f);
    EXPECT_FLOAT_EQ(out.points.colors[200].x, in.colors[200].x);
    ASSERT_EQ(out.points.attributes.size(), in.attributes.size());
    for (const Attribute& a : in.attributes) {
        ASSERT_NE(out.points.attribute(a.name), nullptr) << a.name;
        EXPECT_EQ(out.points.attribute(a.name)->values, a.values) << a.name;
    }
}

}  // namespace
}  // namespace tc
