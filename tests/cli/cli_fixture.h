#pragma once
// The fixture of the CLI tests (cli_test.cpp, transparency_cli_test.cpp): a fresh directory per
// test under the build tree, and run() executing the tubecast binary in it as a user would.
// Test files derive their own fixture (with their own scene writer) from CliFixture:
//     class Cli : public tc::test::CliFixture { ... };
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace tc::test {

struct RunResult {
    int code = -1;
    std::string out, err;
};

// The whole file, empty if it cannot be read.
std::string readText(const std::filesystem::path& p);

// Writes `text` to `p`, creating its parent directories.
void writeText(const std::filesystem::path& p, const std::string& text);

// Writes a 3x3x3-point ASCII .vti (origin 0, spacing 0.5: the box [0, 1]^3) whose point vector
// array `name` is `value` everywhere: a uniform field to trace.
void writeUniformVti(const std::filesystem::path& p, const std::string& name, const std::string& value);

class CliFixture : public ::testing::Test {
protected:
    // dir = TUBECAST_TEST_TMP/cli/<suite>.<test>, emptied.
    void SetUp() override;

    // Runs `env tubecast args` in dir; stdout and stderr go to dir/stdout.txt and dir/stderr.txt.
    RunResult run(const std::string& args, const std::string& env = "");

    std::filesystem::path dir;
};

}  // namespace tc::test
