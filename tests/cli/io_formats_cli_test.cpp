// The line-format readers seen from the binary: malformed .trk/.tck/.obj/.tcb datasets make
// `tubecast render` and `tubecast convert` exit 2 with the file and position in the message
// (before any GL context is made), and `convert` writes .tcb that renders.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "cli_fixture.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

class FormatsCli : public CliFixture {
protected:
    void writeBytes(const std::string& name, const std::vector<std::uint8_t>& bytes) {
        std::ofstream(dir / name, std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    fs::path writeScene(const std::string& dataset) {
        writeText(dir / "scene.json", R"({
  "dataset": {"path": ")" + dataset + R"("},
  "style": {"radius": 0.05},
  "image": {"width": 32, "height": 24},
  "output": {"dir": "out", "name": "f"}
}
)");
        return dir / "scene.json";
    }
    // Renders a scene of `dataset` and expects exit 2 with "DATASET: WHERE" in the message.
    void expectRenderRejects(const std::string& dataset, const std::string& where) {
        writeScene(dataset);
        RunResult r = run("render scene.json");
        EXPECT_EQ(r.code, 2) << r.err;
        EXPECT_NE(r.err.find(dataset + ": " + where), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "out" / "f.png"));
    }
};

std::vector<std::uint8_t> trkHeader() {
    std::vector<std::uint8_t> h(1000, 0);
    std::memcpy(h.data(), "TRACK", 6);
    auto put32 = [&](std::size_t at, std::int32_t v) { std::memcpy(h.data() + at, &v, 4); };
    put32(988, 1);     // n_count
    put32(992, 2);     // version
    put32(996, 1000);  // hdr_size, little-endian
    return h;
}

TEST_F(FormatsCli, RenderOfTrkWithCountBombExitsTwoNamingTheByte) {
    std::vector<std::uint8_t> b = trkHeader();
    const std::int32_t points = 1 << 30;  // far more than the 12 bytes that follow
    b.insert(b.end(), reinterpret_cast<const std::uint8_t*>(&points),
             reinterpret_cast<const std::uint8_t*>(&points) + 4);
    b.resize(b.size() + 12, 0);
    writeBytes("bomb.trk", b);
    expectRenderRejects("bomb.trk", "byte 1000: track 0 declares 1073741824 points");
}

TEST_F(FormatsCli, RenderOfTruncatedTckExitsTwo) {
    std::string head = "mrtrix tracks\ndatatype: Float32LE\nfile: . 64\nEND\n";
    head.resize(64, '\0');
    std::vector<std::uint8_t> b(head.begin(), head.end());
    const float xyz[6] = {0, 0, 0, 1, 1, 1};  // no NaN delimiter, no Inf terminator
    b.insert(b.end(), reinterpret_cast<const std::uint8_t*>(xyz), reinterpret_cast<const std::uint8_t*>(xyz) + 24);
    writeBytes("cut.tck", b);
    expectRenderRejects("cut.tck", "byte 88: truncated");
}

// An MRtrix file of little-endian floats with a 4-digit data offset; `count` as given.
std::vector<std::uint8_t> tckBytes(const std::string& count, const std::vector<float>& values) {
    std::string head = "mrtrix tracks\ndatatype: Float32LE\ncount: " + count + "\nfile: . 0064\nEND\n";
    head.resize(64, '\0');
    // Sized first and filled by memcpy: GCC 12 misreads an insert of the float range as writing
    // past the 64 header bytes (a false -Warray-bounds).
    std::vector<std::uint8_t> b(head.size() + values.size() * sizeof(float));
    std::memcpy(b.data(), head.data(), head.size());
    if (!values.empty()) std::memcpy(b.data() + head.size(), values.data(), values.size() * sizeof(float));
    return b;
}

// A stale count (a tool that stopped before writing it) is a warning that names the line; the
// tracks in the data render.
TEST_F(FormatsCli, RenderOfTckWithStaleCountWarnsAndRenders) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    writeBytes("stale.tck", tckBytes("5", {0, 0, 0, 1, 1, 1, nan, nan, nan, inf, inf, inf}));
    writeScene("stale.tck");
    RunResult r = run("render scene.json");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("warning: stale.tck: line 3: count: 5 tracks declared, the data holds 1; read 1"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(fs::exists(dir / "out" / "f.png"));
}

// An empty tractogram is a valid file of 0 polylines.
TEST_F(FormatsCli, InfoOfEmptyTckSaysZeroPolylines) {
    const float inf = std::numeric_limits<float>::infinity();
    writeBytes("empty.tck", tckBytes("0", {inf, inf, inf}));
    RunResult r = run("info empty.tck --json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\"polylines\": 0"), std::string::npos) << r.out;
}

TEST_F(FormatsCli, RenderOfObjWithBadIndexExitsTwoNamingTheLine) {
    writeText(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nl 1 2 3\n");
    expectRenderRejects("bad.obj", "line 3: vertex index 3 out of range");
}

TEST_F(FormatsCli, RenderOfTcbWithBadMagicExitsTwo) {
    writeBytes("bad.tcb", std::vector<std::uint8_t>(64, 'x'));
    expectRenderRejects("bad.tcb", "byte 0: not a .tcb file");
}

TEST_F(FormatsCli, ConvertRejectsMalformedInputAndUnknownOutputs) {
    writeText(dir / "bad.obj", "v 0 0 0\nv 1 0 x\n");
    RunResult r = run("convert bad.obj out.tcb");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("bad.obj: line 2: expected a number"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out.tcb"));

    writeText(dir / "good.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n");
    r = run("convert good.obj out.ply");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("out.ply: output must end in .vtp"), std::string::npos) << r.err;
}

// obj -> tcb -> vtp keeps the lines (and their NaN vertex is reported, not rendered), and the
// .tcb renders.
TEST_F(FormatsCli, ConvertWritesTcbThatRendersAndConvertsOn) {
    writeText(dir / "lines.obj",
              "a speed\nv 0 0 0\nv 1 0 0\nv nan 1 0\nv 1 1 0\nv 0 1 1\nv 2 2 2\n"
              "vt 1\nvt 2\nvt 3\nvt 4\nvt 5\nvt 6\nl 1 2 3 4 5\nl 5 6\n");
    RunResult r = run("convert lines.obj lines.tcb");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("wrote lines.tcb (3 polylines, 3 segments)"), std::string::npos) << r.err;
    r = run("convert lines.tcb lines.vtp");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("(3 polylines, 3 segments)"), std::string::npos) << r.err;

    writeScene("lines.tcb");
    r = run("render scene.json -q");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out" / "f.png"));
}

}  // namespace
