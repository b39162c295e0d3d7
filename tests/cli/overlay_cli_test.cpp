// Overlays and movies through the tubecast binary: the legend drawn into the PNG is the colormap
// at its ticks and leaves the EXR as rendered, a {frame} label changes only its own pixels, the
// triad follows the animated camera, and `tubecast encode` / output.video write an H.264 MP4
// that ffprobe reads back with the frames and rate asked for.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "core/animation.h"
#include "core/color.h"
#include "core/colormap.h"
#include "core/overlay.h"
#include "core/scene.h"
#include "core/styling.h"
#include "io/dataset.h"
#include "io/image_io.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

class Overlay : public CliFixture {
protected:
    // Tornado lines coloured by speed, 160x120 over opaque black.
    // `extra`: more top-level keys; `output`: more keys of "output".
    fs::path writeScene(const std::string& extra, const std::string& name = "scene.json",
                        const std::string& outDir = "out", const std::string& output = "") {
        const std::string text = R"({
  "dataset": {"generate": "tornado", "lines": 20, "points": 30, "seed": 3},
  "style": {"radius": 0.02, "color": {"attribute": "speed", "colormap": "viridis"}},
  "image": {"width": 160, "height": 120, "background": [0, 0, 0, 1]},
  "output": {"dir": ")" + outDir +
                                 R"(", "name": "f.####")" + output + "}" + extra + "\n}\n";
        writeText(dir / name, text);
        return dir / name;
    }

    static bool haveFont() { return fs::exists(tc::kDefaultOverlayFont); }
};

// The pixel (x, y) of an image read by readImageRgba, as 8-bit sRGB values / 255.
glm::vec3 rgbAt(const tc::RgbaImage& image, int x, int y) {
    const float* p = &image.rgba[4 * (std::size_t(y) * std::size_t(image.width) + std::size_t(x))];
    return {p[0], p[1], p[2]};
}

// "stream=nb_read_frames,r_frame_rate,codec_name" of the first video stream, or "" without ffprobe.
std::string ffprobe(const fs::path& movie) {
    const std::string command =
        "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
        "stream=codec_name,nb_read_frames,r_frame_rate -of default=noprint_wrappers=1 '" +
        movie.string() + "' 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return "";
    std::string out;
    char buffer[256];
    while (fgets(buffer, sizeof buffer, pipe)) out += buffer;
    pclose(pipe);
    return out;
}

bool haveFfmpeg() {
    return std::system("ffmpeg -version > /dev/null 2>&1") == 0 &&
           std::system("ffprobe -version > /dev/null 2>&1") == 0;
}

TEST_F(Overlay, LegendColoursAreTheColormapAtTheTicksAndTheExrIsUntouched) {
    if (!haveFont()) GTEST_SKIP() << tc::kDefaultOverlayFont << " missing: install fonts-dejavu-core";
    writeScene(R"(, "overlay": {"legend": {}})", "legend.json", "legend");
    writeScene("", "plain.json", "plain");
    ASSERT_EQ(run("render -q legend.json").code, 0) << readText(dir / "stderr.txt");
    ASSERT_EQ(run("render -q plain.json").code, 0) << readText(dir / "stderr.txt");

    // The EXR is the rendered frame, channel for channel.
    const tc::FrameImages withLegend = tc::readExr((dir / "legend/f.0000.exr").string());
    const tc::FrameImages plain = tc::readExr((dir / "plain/f.0000.exr").string());
    EXPECT_EQ(withLegend.rgba, plain.rgba);
    EXPECT_EQ(withLegend.depth, plain.depth);
    EXPECT_EQ(withLegend.normal, plain.normal);

    // The range the styling used: the speed attribute's over the loaded lines.
    const tc::Scene scene = tc::loadScene((dir / "legend.json").string());
    const tc::DatasetLoad data = tc::loadDataset(scene.dataset);
    const std::optional<tc::ValueRange> range = tc::colorMappingRange(data.lines, scene.style, scene.file);
    ASSERT_TRUE(range);
    ASSERT_LT(range->lo, range->hi);
    const tc::LegendLayout l = tc::layoutLegend(*scene.overlay.legend, 160, 120, range->lo, range->hi);
    // The labels read as the attribute's range at the bar's ends.
    EXPECT_EQ(l.ticks.front().value, range->lo);
    EXPECT_EQ(l.ticks.back().value, range->hi);
    EXPECT_EQ(l.ticks.front().label, tc::formatLegendValue(range->lo, 0.0));
    EXPECT_EQ(l.ticks.back().label, tc::formatLegendValue(range->hi, 0.0));

    const tc::RgbaImage png = tc::readImageRgba((dir / "legend/f.0000.png").string());
    const tc::RgbaImage plainPng = tc::readImageRgba((dir / "plain/f.0000.png").string());
    const tc::Colormap& viridis = tc::builtinColormap("viridis");
    ASSERT_GE(l.ticks.size(), 2u);
    for (std::size_t i = 0; i < l.ticks.size(); ++i) {
        const glm::ivec2 p = l.tickPixels[i];
        const float t = tc::legendPixelT(l, p.x, p.y);
        EXPECT_NEAR(t, l.ticks[i].t, 0.5f / float(l.bar.height()) + 1e-6f);  // the tick's own pixel
        const glm::vec3 expected = viridis.sampleSrgb(t), got = rgbAt(png, p.x, p.y);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1.0f / 255.0f) << l.ticks[i].label << " c" << c;
        EXPECT_NE(got, rgbAt(plainPng, p.x, p.y));  // drawn, not the frame's own pixel
    }
    // Away from the legend (the image's left half), the PNG is the plain one.
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 80; ++x) ASSERT_EQ(rgbAt(png, x, y), rgbAt(plainPng, x, y)) << x << "," << y;
}

TEST_F(Overlay, FrameLabelDiffersBetweenFramesOnlyWhereTheLabelIs) {
    if (!haveFont()) GTEST_SKIP() << tc::kDefaultOverlayFont << " missing: install fonts-dejavu-core";
    // Two frames of one view: only the label can differ.
    writeScene(R"(, "animation": {"type": "orbit", "frames": 2, "degrees": 0},
  "overlay": {"text": [{"content": "frame {frame}", "position": [0.05, 0.1], "size": 0.1}]})");
    ASSERT_EQ(run("render -q scene.json").code, 0) << readText(dir / "stderr.txt");
    const tc::RgbaImage a = tc::readImageRgba((dir / "out/f.0000.png").string());
    const tc::RgbaImage b = tc::readImageRgba((dir / "out/f.0001.png").string());
    // The label: 12-pixel text on the baseline at (8, 108); "frame 0" is under 7 x 0.7 em wide.
    const int x0 = 8, baseline = 108, px = 12;
    int differing = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < 160; ++x) {
            if (rgbAt(a, x, y) == rgbAt(b, x, y)) continue;
            ++differing;
            EXPECT_TRUE(x >= x0 && x < x0 + 7 * px && y >= baseline - px && y <= baseline + px / 3)
                << "pixel " << x << "," << y << " differs outside the label";
        }
    EXPECT_GT(differing, 5);  // "0" and "1" differ
    // The EXRs hold the rendered frames: the same view twice.
    EXPECT_EQ(tc::readExr((dir / "out/f.0000.exr").string()).rgba, tc::readExr((dir / "out/f.0001.exr").string()).rgba);
}

TEST_F(Overlay, TriadFollowsTheAnimatedCamera) {
    if (!haveFont()) GTEST_SKIP() << tc::kDefaultOverlayFont << " missing: install fonts-dejavu-core";
    writeScene(R"(, "camera": {"eye": [0.5, 0.5, 4], "target": [0.5, 0.5, 0.5], "up": [0, 1, 0]},
  "animation": {"type": "orbit", "frames": 4, "axis": [0, 1, 0], "degrees": 360},
  "overlay": {"axes": {"labels": false, "size": 0.2}})");
    ASSERT_EQ(run("render -q --frames 0,1 scene.json").code, 0) << readText(dir / "stderr.txt");
    const tc::Scene scene = tc::loadScene((dir / "scene.json").string());
    const tc::TriadLayout t = tc::layoutTriad(*scene.overlay.axes, 160, 120);
    const glm::vec3 blue{0.3f, 0.45f, 1.0f}, red{0.95f, 0.2f, 0.2f};
    for (int frame : {0, 1}) {
        const tc::Camera camera = tc::cameraAtFrame(scene.animation, scene.camera.camera, frame);
        const auto axes = tc::triadAxes(camera);
        const tc::RgbaImage png = tc::readImageRgba((dir / ("out/f.000" + std::to_string(frame) + ".png")).string());
        // Frame 0 sees X to the right, frame 1 (a quarter turn) sees Z to the left or right: the
        // axis the camera sees side-on is drawn where triadAxes says.
        const int axis = frame == 0 ? 0 : 2;
        ASSERT_GT(std::abs(axes[std::size_t(axis)].screen.x), 0.99f);
        const glm::vec3 colour = axis == 0 ? red : blue;
        float sumX = 0;
        int n = 0;
        for (int y = 0; y < 120; ++y)
            for (int x = 0; x < 160; ++x)
                if (glm::length(rgbAt(png, x, y) - colour) < 0.03f) {
                    sumX += float(x) + 0.5f - t.origin.x;
                    ++n;
                }
        ASSERT_GT(n, 5) << "frame " << frame;
        EXPECT_GT(sumX / float(n) * axes[std::size_t(axis)].screen.x, 0.3f * t.length) << "frame " << frame;
    }
}

TEST_F(Overlay, MissingFontIsAnInputErrorBeforeAnyFrame) {
    writeScene(R"(, "overlay": {"legend": true, "font": "no/such/font.ttf"})");
    const RunResult r = run("render scene.json");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("error: scene.json: overlay.font: no/such/font.ttf: no such file"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("fonts-dejavu-core"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out/f.0000.png"));
}

// Ten small PNG frames f.0000.png .. f.0009.png, each a different grey.
void writeFrames(const fs::path& out) {
    fs::create_directories(out);
    for (int i = 0; i < 10; ++i) {
        tc::FrameImages f;
        f.width = 32;
        f.height = 24;
        f.rgba.assign(4 * 32 * 24, 1.0f);
        for (std::size_t p = 0; p < f.rgba.size(); p += 4) f.rgba[p] = f.rgba[p + 1] = f.rgba[p + 2] = float(i) / 9;
        char name[32];
        std::snprintf(name, sizeof name, "f.%04d.png", i);
        tc::writePng(f, (out / name).string());
    }
}

TEST_F(Overlay, EncodeWritesAnMp4OfEveryFrameAtTheRequestedRate) {
    if (!haveFfmpeg()) GTEST_SKIP() << "ffmpeg/ffprobe not on PATH: install the Debian package ffmpeg";
    writeFrames(dir / "frames");
    const RunResult r = run("encode frames movie.mp4 --fps 24 --name f.#### --frames 0..9");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("tubecast: encode: "), std::string::npos) << r.err;  // the command line used
    EXPECT_NE(r.err.find("libx264"), std::string::npos) << r.err;
    const std::string probe = ffprobe(dir / "movie.mp4");
    EXPECT_NE(probe.find("codec_name=h264"), std::string::npos) << probe;
    EXPECT_NE(probe.find("r_frame_rate=24/1"), std::string::npos) << probe;
    EXPECT_NE(probe.find("nb_read_frames=10"), std::string::npos) << probe;
    // No temporary files are left next to the movie.
    int entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
    EXPECT_EQ(entries, 4) << "frames, movie.mp4, stdout.txt, stderr.txt";

    // An existing movie is kept without --overwrite.
    EXPECT_EQ(run("encode frames movie.mp4 --name f.#### --frames 0..9").code, 4);
    EXPECT_EQ(run("encode frames movie.mp4 --name f.#### --frames 0..9 --overwrite").code, 0);
}

TEST_F(Overlay, EncodeNamesTheMissingFrames) {
    writeFrames(dir / "frames");
    fs::remove(dir / "frames/f.0003.png");
    fs::remove(dir / "frames/f.0007.png");
    const RunResult r = run("encode frames movie.mp4 --name f.#### --frames 0..9");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("frames: 2 of 10 frame(s) missing: 3,7 (f.0003.png, f.0007.png)"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "movie.mp4"));
}

TEST_F(Overlay, OutputVideoIsEncodedAfterACompleteRunAndEncodeReadsTheRunJson) {
    if (!haveFfmpeg()) GTEST_SKIP() << "ffmpeg/ffprobe not on PATH: install the Debian package ffmpeg";
    writeScene(R"(, "animation": {"type": "orbit", "frames": 3})", "scene.json", "out",
               R"(, "video": {"file": "orbit.mp4", "fps": 12})");
    // Part of the frames: no movie yet, and the log says why.
    RunResult r = run("render --frames 0..1 scene.json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out/orbit.mp4"));
    EXPECT_NE(r.err.find("output.video: not encoded yet: out: 1 of 3 frame(s) missing: 2 (f.0002.png)"),
              std::string::npos)
        << r.err;
    // Resumed to completion: encoded.
    r = run("render --resume scene.json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("tubecast: encode: "), std::string::npos) << r.err;
    std::string probe = ffprobe(dir / "out/orbit.mp4");
    EXPECT_NE(probe.find("nb_read_frames=3"), std::string::npos) << probe;
    EXPECT_NE(probe.find("r_frame_rate=12/1"), std::string::npos) << probe;
    // The frames and names from out/run.json.
    ASSERT_EQ(run("encode out again.mp4 --fps 6").code, 0) << readText(dir / "stderr.txt");
    probe = ffprobe(dir / "again.mp4");
    EXPECT_NE(probe.find("nb_read_frames=3"), std::string::npos) << probe;
    EXPECT_NE(probe.find("r_frame_rate=6/1"), std::string::npos) << probe;
    // The movie is an output: a fresh run does not clobber it.
    for (const auto& e : fs::directory_iterator(dir / "out"))
        if (e.path().filename() != "orbit.mp4") fs::remove(e.path());
    r = run("render scene.json");
    EXPECT_EQ(r.code, 4);
    EXPECT_NE(r.err.find("orbit.mp4: exists (output.video; use --overwrite to replace it or --resume)"),
              std::string::npos)
        << r.err;
}

}  // namespace
