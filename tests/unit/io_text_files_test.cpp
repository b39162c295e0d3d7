#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "io/json_file.h"
#include "io/timings_csv.h"
#include "test_tmp.h"

namespace fs = std::filesystem;

namespace tc {
namespace {

using tc::test::testDir;  // a fresh directory per test (test_tmp.h)

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

TEST(TimingsCsv, header_rows_three_decimals_and_empty_unknown_gpu_time) {
    std::string path = testDir() + "/timings.csv";
    {
        TimingsCsv csv(path, false);
        csv.write({{0, "geometry", 1.23456, 0.5, 1200}, {0, "resolve", -1.0, 2.0, 0}});
        // Flushed per write: a killed run keeps this frame.
        EXPECT_EQ(readText(path), "frame,stage,gpu_ms,cpu_ms,items\n0,geometry,1.235,0.500,1200\n0,resolve,,2.000,0\n");
        csv.write({{1, "a,b", 0.0, 0.0, 18446744073709551615ull}});
    }
    EXPECT_EQ(readText(path),
              "frame,stage,gpu_ms,cpu_ms,items\n0,geometry,1.235,0.500,1200\n0,resolve,,2.000,0\n"
              "1,\"a,b\",0.000,0.000,18446744073709551615\n");
}

TEST(TimingsCsv, append_keeps_rows_and_writes_no_second_header) {
    std::string path = testDir() + "/timings.csv";
    TimingsCsv(path, true).write({{0, "s", 1, 1, 1}});
    TimingsCsv(path, true).write({{1, "s", 2, 2, 2}});
    EXPECT_EQ(readText(path), "frame,stage,gpu_ms,cpu_ms,items\n0,s,1.000,1.000,1\n1,s,2.000,2.000,2\n");
    TimingsCsv(path, false).write({{5, "s", 0, 0, 0}});  // not appending: truncated
    EXPECT_EQ(readText(path), "frame,stage,gpu_ms,cpu_ms,items\n5,s,0.000,0.000,0\n");
}

TEST(TimingsCsv, unwritable_path_is_an_output_error) {
    std::string path = testDir() + "/missing/dir/t.csv";
    try {
        TimingsCsv csv(path, false);
        FAIL() << "no OutputError";
    } catch (const OutputError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": cannot write: No such file or directory");
    }
}

TEST(JsonFile, round_trip_through_an_atomic_file) {
    std::string dir = testDir();
    std::string path = dir + "/stats.json";
    nlohmann::json value = {{"frames", 3}, {"technique", "kbuffer"}, {"ms", {1.5, 2.25}}};
    writeJsonFile(path, value);
    EXPECT_EQ(readJsonFile(path), value);
    EXPECT_EQ(readText(path).back(), '\n');
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
}

TEST(JsonFile, parse_error_names_line_and_column) {
    std::string path = writeText(testDir() + "/scene.json", "{\n  \"a\": 1,\n  \"b\": tru\n}\n");
    try {
        readJsonFile(path);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        // Line 3, column 10: the 'tru' literal is rejected at the newline that ends it.
        EXPECT_EQ(std::string(e.what()).rfind(path + ":3:", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("syntax error"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find("json.exception"), std::string::npos) << e.what();
    }
}

TEST(JsonFile, error_position_matches_the_offending_character) {
    std::string path = writeText(testDir() + "/s.json", "{\"a\": 1,\n \"b\": 2,,}");
    try {
        readJsonFile(path);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        // The second comma is line 2, column 9.
        EXPECT_EQ(std::string(e.what()).rfind(path + ":2:9: syntax error", 0), 0u) << e.what();
    }
}

TEST(JsonFile, truncated_input_points_past_the_end) {
    std::string path = writeText(testDir() + "/t.json", "{\"a\": [1, 2");
    try {
        readJsonFile(path);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ":1:12: ", 0), 0u) << e.what();
    }
}

TEST(JsonFile, missing_file) {
    std::string path = testDir() + "/none.json";
    try {
        readJsonFile(path);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), path + ": no such file");
    }
}

TEST(TextPosition, lines_and_columns_are_one_based) {
    std::string text = "ab\ncd\n";
    EXPECT_EQ(textPosition(text, 0).line, 1u);
    EXPECT_EQ(textPosition(text, 0).column, 1u);
    EXPECT_EQ(textPosition(text, 4).line, 2u);
    EXPECT_EQ(textPosition(text, 4).column, 2u);
    EXPECT_EQ(textPosition(text, 6).line, 3u);
    EXPECT_EQ(textPosition(text, 6).column, 1u);
}

}  // namespace
}  // namespace tc
