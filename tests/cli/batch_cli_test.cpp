// Batch rendering through the binary (docs/batch.md): shards with per-shard side files, --resume
// with completeness and scene-hash checks, --keep-going, placeholders, merge-timings, the EXR
// camera metadata and JSON-lines progress.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/batch.h"
#include "cli_fixture.h"
#include "io/atomic_file.h"
#include "io/image_io.h"

namespace fs = std::filesystem;
using namespace tc::test;

namespace {

class Batch : public CliFixture {
protected:
    // 20 tornado lines on a 4-frame orbit, 32x24, PNG + EXR; camera given explicitly so the
    // EXR's worldToCamera can be checked against it.
    void writeScene(const std::string& extra = "") {
        writeText(dir / "scene.json", R"({
  "dataset": {"generate": "tornado", "lines": 20, "points": 30, "seed": 3},
  "style": {"radius": 0.02},
  "camera": {"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 40},
  "animation": {"type": "orbit", "frames": 4, "axis": [0, 1, 0], "degrees": 360},
  "image": {"width": 32, "height": 24},
  "output": {"dir": "out", "name": "f.####", "aovs": ["depth"]})" +
                                          extra + "\n}\n");
    }
    fs::path out(const std::string& name) const { return dir / "out" / name; }
    std::vector<int> framesIn(const std::string& csv) const {
        std::vector<int> frames;
        std::istringstream in(readText(out(csv)));
        std::string line;
        std::getline(in, line);
        while (std::getline(in, line))
            if (line.find(",frame,") != std::string::npos) frames.push_back(std::stoi(line));
        return frames;
    }
};

TEST_F(Batch, ShardsSharingADirectoryWriteDisjointFramesAndOwnSideFiles) {
    writeScene();
    ASSERT_EQ(run("render scene.json -q --shard 0/2").code, 0);
    RunResult r = run("render scene.json -q --shard 1/2");
    ASSERT_EQ(r.code, 0) << r.err;
    for (int f = 0; f < 4; ++f) {
        EXPECT_TRUE(fs::exists(out("f.000" + std::to_string(f) + ".png"))) << f;
        EXPECT_TRUE(fs::exists(out("f.000" + std::to_string(f) + ".exr"))) << f;
    }
    EXPECT_EQ(framesIn("timings.0-of-2.csv"), (std::vector<int>{0, 2}));
    EXPECT_EQ(framesIn("timings.1-of-2.csv"), (std::vector<int>{1, 3}));
    EXPECT_FALSE(fs::exists(out("timings.csv")));
    auto run1 = nlohmann::json::parse(readText(out("run.1-of-2.json")));
    EXPECT_EQ(run1["frames_rendered"], (std::vector<int>{1, 3}));
    EXPECT_EQ(run1["shard"]["count"], 2);

    // merge-timings: one header, shard rows concatenated in argument order.
    r = run("merge-timings out/all.csv out/timings.0-of-2.csv out/timings.1-of-2.csv");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(framesIn("all.csv"), (std::vector<int>{0, 2, 1, 3}));
    EXPECT_EQ(run("merge-timings out/all.csv out/timings.0-of-2.csv").code, 4);  // exists, no --overwrite
}

TEST_F(Batch, ShardOfAFrameSelectionAndSlurmEnvironment) {
    writeScene();
    // --frames 1..3 -> list {1,2,3}; the Slurm task 11 of --array=10-11 is shard 1/2 -> {2}.
    RunResult r = run("render scene.json -q --frames 1..3 --shard slurm",
                      "SLURM_ARRAY_TASK_ID=11 SLURM_ARRAY_TASK_MIN=10 SLURM_ARRAY_TASK_COUNT=2");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(framesIn("timings.1-of-2.csv"), (std::vector<int>{2}));
    EXPECT_EQ(run("render scene.json --shard 2/2").code, 2);
}

TEST_F(Batch, ResumeSkipsCompleteFramesAndRerendersTruncatedOnes) {
    writeScene();
    ASSERT_EQ(run("render scene.json -q --frames 0..2").code, 0);
    const std::string frame0 = readText(out("f.0000.png"));
    std::string frame1 = readText(out("f.0001.exr"));
    writeText(dir / "frame1.exr", frame1);
    // A truncated EXR (e.g. copied from a full disk): exists, but its pixels do not decode.
    writeText(out("f.0001.exr"), frame1.substr(0, frame1.size() / 2));
    fs::last_write_time(out("f.0000.png"), fs::file_time_type::clock::now() - std::chrono::hours(1));
    const auto stamp0 = fs::last_write_time(out("f.0000.png"));

    RunResult r = run("render scene.json --resume");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("frame 1 re-rendered"), std::string::npos) << r.err;
    EXPECT_EQ(fs::last_write_time(out("f.0000.png")), stamp0);  // complete: not touched
    EXPECT_EQ(readText(out("f.0000.png")), frame0);
    EXPECT_NO_THROW(tc::verifyImage(out("f.0001.exr").string()));
    EXPECT_EQ(tc::compareImages(out("f.0001.exr").string(), (dir / "frame1.exr").string(), 0.0f).maxError, 0.0);
    // Appended: the first run's frames 0..2, then 1 (truncated) and 3 (never rendered).
    EXPECT_EQ(framesIn("timings.csv"), (std::vector<int>{0, 1, 2, 1, 3}));

    r = run("render scene.json --resume");
    ASSERT_EQ(r.code, 0);
    EXPECT_NE(r.err.find("nothing to render"), std::string::npos) << r.err;
}

TEST_F(Batch, ResumeRerendersFramesOfAnotherSceneAndDryRunListsThem) {
    writeScene();
    ASSERT_EQ(run("render scene.json -q").code, 0);
    auto meta = tc::verifyImage(out("f.0002.png").string());
    const std::string hash = meta.at(tc::cli::kSceneHashKey);
    EXPECT_EQ(hash.size(), 40u);
    EXPECT_EQ(tc::verifyImage(out("f.0002.exr").string()).at(tc::cli::kSceneHashKey), hash);

    // Only the output placement differs: same hash, nothing to do.
    RunResult r = run("render scene.json --resume --dry-run --set 'output.formats=[\"png\",\"exr\"]'");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, "\n");
    // A style change is another scene: every frame is due.
    r = run("render scene.json --resume --dry-run --set style.radius=0.03");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, "0..3\n");
    EXPECT_NE(r.err.find("rendered from another scene"), std::string::npos) << r.err;
    fs::remove(out("f.0002.exr"));
    r = run("render scene.json --resume --dry-run -q");
    EXPECT_EQ(r.out, "2\n");

    r = run("render scene.json --resume -q --set style.radius=0.03");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(tc::verifyImage(out("f.0000.png").string()).at(tc::cli::kSceneHashKey), hash);
}

TEST_F(Batch, KeepGoingWritesTheOtherFramesAndExitsWith5) {
    writeScene();
    // Frame 1 cannot be written: its final name is a non-empty directory.
    fs::create_directories(out("f.0001.png"));
    writeText(out("f.0001.png") / "keep", "x");
    RunResult r = run("render scene.json -q --resume --keep-going --log-format json");
    EXPECT_EQ(r.code, 5) << r.err;
    EXPECT_NE(r.err.find("1 of 4 frame(s) failed: 1"), std::string::npos) << r.err;
    for (const char* f : {"f.0000.png", "f.0002.png", "f.0003.png", "f.0003.exr"}) EXPECT_TRUE(fs::exists(out(f))) << f;
    auto run0 = nlohmann::json::parse(readText(out("run.json")));
    EXPECT_EQ(run0["frames_failed"], (std::vector<int>{1}));
    // JSON lines on stdout: start, one event per frame, done.
    std::istringstream lines(r.out);
    std::vector<nlohmann::json> events;
    for (std::string line; std::getline(lines, line);) events.push_back(nlohmann::json::parse(line));
    ASSERT_EQ(events.size(), 6u) << r.out;
    EXPECT_EQ(events.front()["event"], "start");
    EXPECT_EQ(events[2]["event"], "failed");
    EXPECT_EQ(events[2]["frame"], 1);
    EXPECT_EQ(events[4]["event"], "frame");
    EXPECT_EQ(events[4]["done"], 4);
    EXPECT_EQ(events[4]["eta_s"], 0.0);
    EXPECT_EQ(events.back()["failed"], (std::vector<int>{1}));

    // Without --keep-going the first failure ends the run with its own code.
    fs::remove(out("f.0000.png"));
    r = run("render scene.json -q --resume");
    EXPECT_EQ(r.code, 4) << r.err;
}

TEST_F(Batch, PlaceholdersSkipFramesHeldByLiveProcessesAndTakeOverStaleOnes) {
    writeScene();
    fs::create_directories(dir / "out");
    using tc::cli::PlaceholderInfo;
    // Frame 1 is held by this (live) test process; frame 2 by one that died.
    writeText(out(".f.0001.placeholder"),
              tc::cli::toJson(PlaceholderInfo{tc::hostName(), long(getpid()), "77_1", tc::cli::unixNow()}).dump());
    writeText(out(".f.0002.placeholder"),
              tc::cli::toJson(PlaceholderInfo{tc::hostName(), 999999999L, "77_2", tc::cli::unixNow()}).dump());
    RunResult r = run("render scene.json --placeholders --set 'output.formats=[\"png\"]'");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("frame 1 skipped: being rendered by " + tc::hostName()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("(job 77_1)"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out("f.0001.png")));
    for (const char* f : {"f.0000.png", "f.0002.png", "f.0003.png"}) EXPECT_TRUE(fs::exists(out(f))) << f;
    EXPECT_FALSE(fs::exists(out(".f.0002.placeholder")));  // taken over and released
    EXPECT_TRUE(fs::exists(out(".f.0001.placeholder")));   // someone else's: left alone
    // An old heartbeat from another host is stale after --placeholder-timeout.
    writeText(out(".f.0001.placeholder"),
              tc::cli::toJson(PlaceholderInfo{"elsewhere", 1, "", tc::cli::unixNow() - 30}).dump());
    r = run("render scene.json -q --resume --placeholders --placeholder-timeout 10 --set 'output.formats=[\"png\"]'");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(out("f.0001.png")));
    EXPECT_EQ(framesIn("timings.csv"), (std::vector<int>{0, 2, 3, 1}));
}

TEST_F(Batch, ExrCarriesCameraMatricesRenderTimeAndVersion) {
    writeScene();
    ASSERT_EQ(run("render scene.json -q --frames 0").code, 0);
    auto in = OIIO::ImageInput::open(out("f.0000.exr").string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    const OIIO::ParamValue* w2c = spec.find_attribute("worldToCamera", OIIO::TypeMatrix44);
    const OIIO::ParamValue* w2ndc = spec.find_attribute("worldToNDC", OIIO::TypeMatrix44);
    ASSERT_TRUE(w2c && w2ndc);
    // Imath row-vector convention: p * M. Frame 0's eye (0,0,3) maps to the camera origin and the
    // target (0,0,0) to 3 units down -z.
    glm::mat4 m = glm::make_mat4(static_cast<const float*>(w2c->data()));
    glm::vec4 eye = m * glm::vec4(0, 0, 3, 1), target = m * glm::vec4(0, 0, 0, 1);
    EXPECT_NEAR(glm::length(glm::vec3(eye)), 0.0f, 1e-5f);
    EXPECT_NEAR(target.z, -3.0f, 1e-5f);
    // The target is at the centre of the image: NDC x = y = 0.
    glm::vec4 ndc = glm::make_mat4(static_cast<const float*>(w2ndc->data())) * glm::vec4(0, 0, 0, 1);
    EXPECT_NEAR(ndc.x / ndc.w, 0.0f, 1e-5f);
    EXPECT_NEAR(ndc.y / ndc.w, 0.0f, 1e-5f);
    EXPECT_GT(spec.get_float_attribute("tubecast:renderSeconds", -1.0f), 0.0f);
    EXPECT_EQ(spec.get_string_attribute("tubecast:version"), TUBECAST_VERSION);
    EXPECT_FALSE(spec.get_string_attribute("tubecast:renderer").empty());
}

}  // namespace
