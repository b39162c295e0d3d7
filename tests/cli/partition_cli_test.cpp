// `tubecast partition` seen from the binary: a scene's lines partitioned into bricks come back
// byte-identical through `convert` and render the same image as the scene's own dataset; existing
// partitions are kept unless --overwrite; a broken partitioned set is exit 2 naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

class PartitionCli : public CliFixture {
protected:
    void writeScene(const std::string& name, const std::string& dataset) {
        writeText(dir / name, R"({
  "dataset": )" + dataset + R"(,
  "style": {"radius": 0.02, "color": {"attribute": "line_length"}},
  "image": {"width": 48, "height": 32},
  "output": {"dir": "out-)" + name +
                                  R"(", "name": "f"}
}
)");
    }
    void SetUp() override {
        CliFixture::SetUp();
        writeScene("scene.json", R"({"generate": "tornado", "lines": 40, "points": 80})");
    }
};

TEST_F(PartitionCli, PartitionedSceneConvertsBackToTheSameTcb) {
    RunResult r = run("partition scene.json -n 3 -o parts");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("wrote parts/index.json and 3 bricks"), std::string::npos) << r.err;
    for (const char* name : {"index.json", "region-0.tcb", "region-1.tcb", "region-2.tcb", "region-2.runs"})
        EXPECT_TRUE(fs::exists(dir / "parts" / name)) << name;
    const nlohmann::json index = nlohmann::json::parse(readText(dir / "parts" / "index.json"));
    EXPECT_EQ(index["format"], "tubecast-partition");
    EXPECT_EQ(index["regions"].size(), 3u);
    EXPECT_FLOAT_EQ(index["radius"].get<float>(), 0.02f);  // the scene's radius
    // The scene's style names a derived attribute that needs whole polylines: it is stored.
    bool lineLength = false;
    for (const auto& a : index["attributes"]) lineLength = lineLength || a["name"] == "line_length";
    EXPECT_TRUE(lineLength);

    ASSERT_EQ(run("convert scene.json direct.tcb").code, 0);
    ASSERT_EQ(run("convert parts whole.tcb").code, 0);
    ASSERT_EQ(run("convert parts/index.json whole2.tcb").code, 0);
    // The original's attributes plus line_length: compare the geometry through a partition of a
    // dataset file instead, which adds nothing.
    r = run("partition direct.tcb -n 4 -o parts4");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(run("convert parts4 whole4.tcb").code, 0);
    EXPECT_EQ(readText(dir / "whole4.tcb"), readText(dir / "direct.tcb"));
    EXPECT_EQ(readText(dir / "whole.tcb"), readText(dir / "whole2.tcb"));
    EXPECT_GT(fs::file_size(dir / "whole.tcb"), fs::file_size(dir / "direct.tcb"));  // + line_length
}

TEST_F(PartitionCli, PartitionedDatasetRendersLikeTheScenesOwnDataset) {
    ASSERT_EQ(run("partition scene.json -n 4 -o parts").code, 0);
    writeScene("parts.json", R"({"path": "parts"})");
    RunResult a = run("render scene.json -q");
    ASSERT_EQ(a.code, 0) << a.err;
    RunResult b = run("render parts.json -q");
    ASSERT_EQ(b.code, 0) << b.err;
    RunResult c = run("compare out-scene.json/f.png out-parts.json/f.png --fail 200");
    EXPECT_EQ(c.code, 0) << c.out << c.err;
    EXPECT_NE(c.out.find("max_error 0\n"), std::string::npos) << c.out;  // identical pixels
}

TEST_F(PartitionCli, ExistingPartitionIsKeptWithoutOverwrite) {
    ASSERT_EQ(run("partition scene.json -n 2 -o parts").code, 0);
    RunResult r = run("partition scene.json -n 2 -o parts");
    EXPECT_EQ(r.code, 4) << r.err;
    EXPECT_NE(r.err.find("parts/index.json: exists (use --overwrite"), std::string::npos) << r.err;
    r = run("partition scene.json -n 2 -o parts --overwrite");
    EXPECT_EQ(r.code, 0) << r.err;
}

TEST_F(PartitionCli, BadIndexIsExitTwoNamingTheFile) {
    ASSERT_EQ(run("partition scene.json -n 3 -o parts").code, 0);
    std::string text = readText(dir / "parts" / "index.json");
    const std::string version = "\"version\": 1";
    ASSERT_NE(text.find(version), std::string::npos);
    writeText(dir / "parts" / "index.json", text.replace(text.find(version), version.size(), "\"version\": 9"));
    RunResult r = run("info parts");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("error: parts/index.json: version: unsupported partition version 9"), std::string::npos)
        << r.err;

    ASSERT_EQ(run("partition scene.json -n 3 -o parts --overwrite").code, 0);
    fs::remove(dir / "parts" / "region-2.tcb");
    r = run("convert parts/index.json back.tcb");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("error: parts/region-2.tcb: no such file (region 2 of parts/index.json)"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "back.tcb"));
}

TEST_F(PartitionCli, BadArgumentsAndParticlesAreExitTwo) {
    RunResult r = run("partition scene.json -n 0 -o parts");
    EXPECT_EQ(r.code, 2) << r.err;
    writeScene("drops.json", R"({"generate": "droplets", "particles": 100})");
    r = run("partition drops.json -n 2 -o parts");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("particle data: partitioned sets hold lines only"), std::string::npos) << r.err;
    r = run("partition scene.json -n 2 -o parts --radius -1");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_FALSE(fs::exists(dir / "parts" / "index.json"));
}

}  // namespace
