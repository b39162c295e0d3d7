// Runs the tubecast binary the way a user does and checks exit codes, messages and files.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "cli_fixture.h"
#include "io/image_io.h"
#include "io/line_reader.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

// A fresh directory per test under the build tree (cli_fixture.h).
class Cli : public CliFixture {
protected:
    // A tiny but real scene: 20 tornado streamlines, 32x24 pixels.
    fs::path writeScene(const std::string& extra = "", const std::string& name = "scene.json") {
        std::string text = R"({
  "dataset": {"generate": "tornado", "lines": 20, "points": 30, "seed": 3},
  "style": {"radius": 0.02},
  "image": {"width": 32, "height": 24},
  "output": {"dir": "out", "name": "f.####", "aovs": ["depth", "normal", "id"]})" +
                           extra + "\n}\n";
        writeText(dir / name, text);
        return dir / name;
    }
};

TEST_F(Cli, VersionPrintsTheVersionAndExitsZero) {
    RunResult r = run("--version");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("tubecast " TUBECAST_VERSION), std::string::npos) << r.out;
}

TEST_F(Cli, HelpListsTheExitCodes) {
    RunResult r = run("--help");
    EXPECT_EQ(r.code, 0);
    for (const char* code : {"2  invalid input", "3  no usable OpenGL", "4  cannot write output"})
        EXPECT_NE(r.out.find(code), std::string::npos) << code;
}

TEST_F(Cli, UnknownOptionIsAUsageErrorWithExitCode2) {
    RunResult r = run("render --no-such-flag scene.json");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("error:"), std::string::npos);
}

TEST_F(Cli, MissingSceneFileNamesThePath) {
    RunResult r = run("render nope.json");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("nope.json: no such file"), std::string::npos) << r.err;
}

TEST_F(Cli, UnknownSceneKeyNamesFileAndKeyPath) {
    writeScene(R"(, "render": {"technique": "rasterized", "transparancy": "opaque"})");
    RunResult r = run("render scene.json");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("scene.json: render.transparancy: unknown key"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("did you mean \"transparency\""), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out" / "f.0000.png"));
}

TEST_F(Cli, InvalidJsonReportsLineAndColumn) {
    writeText(dir / "broken.json", "{\n  \"dataset\": {\"generate\": \"tornado\",}\n}\n");
    RunResult r = run("validate broken.json");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("broken.json:2:"), std::string::npos) << r.err;
}

TEST_F(Cli, SetOverrideIsTypeCheckedAndNamedAsSet) {
    writeScene();
    RunResult r = run("validate scene.json --set image.width=wide");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--set image.width: expected integer"), std::string::npos) << r.err;
    EXPECT_EQ(run("validate scene.json --set image.width=64").code, 0);
}

TEST_F(Cli, ValidateChecksTheTechniqueAgainstTheRegistry) {
    // The registry (core/technique_registry.h) knows the names and which settings each takes; the
    // scene parser only reads them, so `validate` must ask it.
    writeScene();
    RunResult r = run("validate scene.json --set render.technique=kbuffer");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("scene.json: render.technique: expected one of \"auto\", \"rasterized\", \"spheres\", "
                         "\"voxel_raycast\", \"raytraced\", got \"kbuffer\""),
              std::string::npos)
        << r.err;
    r = run("validate scene.json --set render.technique=raytraced --set render.transparency=opacity_optimization");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("scene.json: render.transparency: technique \"raytraced\" takes"), std::string::npos) << r.err;
    r = run("validate scene.json --set render.technique=spheres --set render.transparency=kbuffer");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("technique \"spheres\" takes \"opaque\" or \"object_order\", got \"kbuffer\""),
              std::string::npos)
        << r.err;
    EXPECT_EQ(run("validate scene.json --set render.technique=spheres --set render.transparency=object_order").code, 0);
}

TEST_F(Cli, MissingDatasetFileIsExit2NamingThePath) {
    writeText(dir / "scene.json", R"({"dataset": {"path": "data/missing.vtp"}, "image": {"width": 16, "height": 16}})");
    RunResult r = run("render scene.json");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("missing.vtp"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
}

TEST_F(Cli, BadFrameListIsExit2) {
    writeScene();
    RunResult r = run("render scene.json --frames 0..5");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--frames 0..5: frame 5 is outside"), std::string::npos) << r.err;
}

// One 4-point polyline whose third vertex is NaN (VTK's ASCII reader cannot parse "nan", so the
// file is written through our own .vtp writer).
void writeNanVtp(const fs::path& path, bool allNan = false) {
    tc::LineSet lines;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    lines.positions = {{0, 0, 0}, {0.5f, 0, 0}, {nan, 0, 0}, {1, 0.2f, 0}};
    if (allNan) lines.positions = {{nan, 0, 0}, {1, nan, 0}};
    lines.offsets = {0, std::uint32_t(lines.positions.size())};
    tc::writeLineSetVtp(lines, path.string());
}

TEST_F(Cli, NanVerticesAreSkippedWithACountAndTheRestRenders) {
    writeNanVtp(dir / "nan.vtp");
    writeText(dir / "scene.json", R"({"dataset": {"path": "nan.vtp"}, "style": {"radius": 0.05},
        "image": {"width": 16, "height": 16}, "output": {"dir": "out", "name": "nan"}})");
    RunResult r = run("render scene.json");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("warning: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("1 non-finite"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out" / "nan.png"));
}

TEST_F(Cli, DatasetWithOnlyNanVerticesIsExit2) {
    writeNanVtp(dir / "nan.vtp", /*allNan=*/true);
    writeText(dir / "scene.json", R"({"dataset": {"path": "nan.vtp"}, "image": {"width": 16, "height": 16}})");
    RunResult r = run("render scene.json");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("nan.vtp"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("no polylines"), std::string::npos) << r.err;
}

TEST_F(Cli, UnwritableOutputDirectoryIsExit4) {
    writeScene();
    writeText(dir / "blocker", "a file where a directory should be");
    RunResult r = run("render scene.json -o blocker/sub");
    EXPECT_EQ(r.code, 4) << r.err;
    EXPECT_NE(r.err.find("blocker/sub"), std::string::npos) << r.err;
}

TEST_F(Cli, NoGlBackendIsExit3) {
    writeScene();
    RunResult r = run("render scene.json", "TUBECAST_FORCE_NO_GL=1");
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("no OpenGL backend"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out" / "f.0000.png"));
}

// A real failure, not the test hook: glvnd finds no EGL vendor library.
TEST_F(Cli, BrokenEglIsExit3NamingEglAndTheAlternative) {
    writeScene();
    RunResult r = run("render scene.json --backend egl", "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json");
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("EGL"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--backend osmesa"), std::string::npos) << r.err;
}

TEST_F(Cli, RenderWritesPngExrTimingsAndRunJson) {
    writeScene(R"(, "render": {"technique": "rasterized"})");  // its stages include gbuffer
    RunResult r = run("render scene.json");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* f : {"f.0000.png", "f.0000.exr", "timings.csv", "run.json"})
        EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
    std::string csv = readText(dir / "out" / "timings.csv");
    EXPECT_EQ(csv.rfind("frame,stage,gpu_ms,cpu_ms,items\n", 0), 0u) << csv;
    EXPECT_NE(csv.find("0,gbuffer,"), std::string::npos) << csv;
    std::string runJson = readText(dir / "out" / "run.json");
    EXPECT_NE(runJson.find("\"renderer\""), std::string::npos);
    // No temp files are left behind.
    for (const auto& e : fs::directory_iterator(dir / "out"))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

TEST_F(Cli, ExistingOutputsAreNeverReplacedWithoutOverwrite) {
    writeScene();
    ASSERT_EQ(run("render scene.json").code, 0);
    auto before = fs::last_write_time(dir / "out" / "f.0000.png");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    RunResult again = run("render scene.json");
    EXPECT_EQ(again.code, 4);
    EXPECT_NE(again.err.find("f.0000.png exists"), std::string::npos) << again.err;
    EXPECT_NE(again.err.find("--resume"), std::string::npos);
    EXPECT_EQ(fs::last_write_time(dir / "out" / "f.0000.png"), before);

    RunResult resumed = run("render scene.json --resume");
    EXPECT_EQ(resumed.code, 0) << resumed.err;
    EXPECT_NE(resumed.err.find("nothing to render"), std::string::npos) << resumed.err;
    EXPECT_EQ(fs::last_write_time(dir / "out" / "f.0000.png"), before);

    RunResult overwritten = run("render scene.json --overwrite");
    EXPECT_EQ(overwritten.code, 0) << overwritten.err;
    EXPECT_NE(fs::last_write_time(dir / "out" / "f.0000.png"), before);
}

TEST_F(Cli, ResumeRendersOnlyTheMissingFramesAndAppendsTimings) {
    writeScene(R"(, "animation": {"type": "orbit", "frames": 3}, "render": {"technique": "rasterized"})");
    ASSERT_EQ(run("render scene.json --frames 0,2").code, 0);
    ASSERT_TRUE(fs::exists(dir / "out" / "f.0002.exr"));
    ASSERT_FALSE(fs::exists(dir / "out" / "f.0001.exr"));
    RunResult r = run("render scene.json --resume");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out" / "f.0001.exr"));
    std::string csv = readText(dir / "out" / "timings.csv");
    EXPECT_NE(csv.find("\n0,gbuffer"), std::string::npos);
    EXPECT_NE(csv.find("\n1,gbuffer"), std::string::npos);
    EXPECT_NE(csv.find("\n2,gbuffer"), std::string::npos);
    EXPECT_EQ(csv.find("frame,stage", 1), std::string::npos) << "header written twice";
}

TEST_F(Cli, InfoJsonReportsCountsBoundsAndAttributes) {
    writeNanVtp(dir / "nan.vtp");
    RunResult r = run("info nan.vtp --json");
    ASSERT_EQ(r.code, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["polylines"], 1);  // the NaN vertex splits off a 1-vertex polyline, which is dropped
    EXPECT_EQ(j["vertices"], 2);
    EXPECT_EQ(j["segments"], 1);
    EXPECT_TRUE(j.contains("bounds"));
    EXPECT_TRUE(j.contains("attributes"));
}

// The two backends run the same llvmpipe; the images must agree exactly.
TEST_F(Cli, EglAndOsmesaRenderTheSameImage) {
    writeScene();
    ASSERT_EQ(run("render scene.json --backend egl -o egl").code, 0);
    RunResult r = run("render scene.json --backend osmesa -o osmesa");
    ASSERT_EQ(r.code, 0) << r.err;
    tc::ImageDiff d =
        tc::compareImages((dir / "egl" / "f.0000.exr").string(), (dir / "osmesa" / "f.0000.exr").string(), 0.0f);
    EXPECT_EQ(d.maxError, 0.0);
    tc::FrameImages a = tc::readExr((dir / "egl" / "f.0000.exr").string());
    tc::FrameImages b = tc::readExr((dir / "osmesa" / "f.0000.exr").string());
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.id, b.id);
}

TEST_F(Cli, OneAndTwoLlvmpipeThreadsRenderIdenticalImages) {
    writeScene();
    ASSERT_EQ(run("render scene.json -o t1", "LP_NUM_THREADS=1").code, 0);
    ASSERT_EQ(run("render scene.json -o t2", "LP_NUM_THREADS=2").code, 0);
    tc::FrameImages a = tc::readExr((dir / "t1" / "f.0000.exr").string());
    tc::FrameImages b = tc::readExr((dir / "t2" / "f.0000.exr").string());
    EXPECT_EQ(a.rgba, b.rgba);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.id, b.id);
}

}  // namespace
