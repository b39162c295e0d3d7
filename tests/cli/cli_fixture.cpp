#include "cli_fixture.h"

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace tc::test {

std::string readText(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void writeText(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

void writeUniformVti(const fs::path& p, const std::string& name, const std::string& value) {
    std::string values;
    for (int i = 0; i < 27; ++i) values += value + " ";
    writeText(p, R"(<?xml version="1.0"?>
<VTKFile type="ImageData" version="0.1" byte_order="LittleEndian">
  <ImageData WholeExtent="0 2 0 2 0 2" Origin="0 0 0" Spacing="0.5 0.5 0.5">
    <Piece Extent="0 2 0 2 0 2">
      <PointData><DataArray type="Float32" Name=")" +
                     name + R"(" NumberOfComponents="3" format="ascii">)" + values +
                     R"(</DataArray></PointData>
    </Piece>
  </ImageData>
</VTKFile>
)");
}

void CliFixture::SetUp() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::path(TUBECAST_TEST_TMP) / "cli" / (std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
}

RunResult CliFixture::run(const std::string& args, const std::string& env) {
    std::string cmd = "cd '" + dir.string() + "' && " + env + (env.empty() ? "" : " ") + TUBECAST_BINARY + " " + args +
                      " > stdout.txt 2> stderr.txt";
    int status = std::system(cmd.c_str());
    RunResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = readText(dir / "stdout.txt");
    r.err = readText(dir / "stderr.txt");
    return r;
}

}  // namespace tc::test
