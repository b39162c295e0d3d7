// Large images through the binary: a k-buffer frame over render.memory_budget_mb is tiled
// automatically (instead of refused) and its EXR equals the untiled frame's in every channel;
// image.samples anti-aliases the colour and keeps one sample's depth and id.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>

#include "cli_fixture.h"
#include "io/image_io.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

class TilingCli : public CliFixture {
protected:
    void writeScene() {
        writeText(dir / "scene.json", R"({
  "dataset": {"generate": "tornado", "lines": 40, "points": 40, "seed": 5},
  "style": {"radius": 0.025, "color": {"attribute": "speed", "colormap": "viridis"}, "opacity": 0.5},
  "camera": {"fit": true, "eye": [1.6, -1.2, 1.25], "target": [0.5, 0.5, 0.5], "up": [0, 0, 1], "fov_deg": 30},
  "image": {"width": 150, "height": 110},
  "render": {"transparency": "kbuffer", "kbuffer": {"k": 8}, "culling": {"enabled": true}},
  "output": {"dir": "out", "name": "f.####", "formats": ["exr"], "aovs": ["depth", "normal", "id"]}
}
)");
    }
};

TEST_F(TilingCli, KbufferOverTheBudgetIsTiledAndEqualsTheUntiledFrame) {
    writeScene();
    // 150 x 110 x (16 + 8 x 8 + 4 + 36 + 2) B = 1.93 MiB > 1 MB: tiled, not refused.
    RunResult tiled = run("render scene.json --set render.memory_budget_mb=1 -o tiled");
    ASSERT_EQ(tiled.code, 0) << tiled.err;
    EXPECT_NE(tiled.err.find("tile(s) (2x1, for render.memory_budget_mb)"), std::string::npos) << tiled.err;
    RunResult full = run("render scene.json -o full");
    ASSERT_EQ(full.code, 0) << full.err;
    EXPECT_EQ(full.err.find("tile(s)"), std::string::npos) << full.err;
    const tc::FrameImages a = tc::readExr((dir / "tiled" / "f.0000.exr").string());
    const tc::FrameImages b = tc::readExr((dir / "full" / "f.0000.exr").string());
    EXPECT_TRUE(a.rgba == b.rgba);
    EXPECT_TRUE(a.depth == b.depth);
    EXPECT_TRUE(a.normal == b.normal);
    EXPECT_TRUE(a.id == b.id);
    std::size_t covered = 0;
    for (std::size_t i = 3; i < b.rgba.size(); i += 4) covered += b.rgba[i] > 0.0f;
    EXPECT_GT(covered, 1000u);
}

TEST_F(TilingCli, SamplesAntiAliasColourAndKeepOneSamplesDepthAndId) {
    writeScene();
    RunResult one = run("render scene.json -o one");
    ASSERT_EQ(one.code, 0) << one.err;
    RunResult aa = run("render scene.json --set image.samples=4 --set image.tiles=[2,2] -o aa");
    ASSERT_EQ(aa.code, 0) << aa.err;
    const tc::FrameImages a = tc::readExr((dir / "aa" / "f.0000.exr").string());
    const tc::FrameImages b = tc::readExr((dir / "one" / "f.0000.exr").string());
    // depth and id come from one sample (never a blend): ids are polyline ids (40 lines) or the
    // background, and depth is infinite exactly on background.
    std::size_t blended = 0;
    for (std::size_t i = 0; i < a.id.size(); ++i) {
        const bool background = a.id[i] == 0xFFFFFFFFu;
        blended += !(background || a.id[i] < 40u) || (background != std::isinf(a.depth[i]));
    }
    EXPECT_EQ(blended, 0u);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) changed += a.rgba[i] != b.rgba[i];
    EXPECT_GT(changed, 100u);
    RunResult bad = run("render scene.json --set image.tiles=[0,2] -o bad");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("image.tiles: expected \"auto\" or [nx, ny]"), std::string::npos) << bad.err;
}

}  // namespace
