// The transparent paths through the tubecast binary: the k-buffer memory budget error, EGL vs
// OSMesa for a k-buffer render, render.reference = "depth_peeling" writing quality.csv, and
// style.halo (which techniques draw it, refusals, auto).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "io/image_io.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

// A fresh directory per test under the build tree (cli_fixture.h, shared with cli_test.cpp).
class TransparencyCli : public CliFixture {
protected:
    // Tornado streamlines with constant opacity; `render` is the body of the "render" object.
    fs::path writeScene(const std::string& render, int lines = 30, int width = 48, int height = 36,
                        float opacity = 0.3f, const std::string& extra = "") {
        std::ostringstream text;
        text << R"({
  "dataset": {"generate": "tornado", "lines": )"
             << lines << R"(, "points": 40, "seed": 3},
  "style": {"radius": 0.02, "color": {"attribute": "speed", "colormap": "viridis"}, "opacity": )"
             << opacity << R"(},
  "camera": {"fit": true, "eye": [1.6, -1.2, 1.25], "target": [0.5, 0.5, 0.5], "up": [0, 0, 1], "fov_deg": 30},
  "image": {"width": )"
             << width << R"(, "height": )" << height << R"(},
  "render": {)"
             << render << R"(},
  "output": {"dir": "out", "name": "f.####", "aovs": ["depth", "normal", "id"]})"
             << extra << "\n}\n";
        writeText(dir / "scene.json", text.str());
        return dir / "scene.json";
    }
};

TEST_F(TransparencyCli, KbufferOverTheMemoryBudgetIsExit2NamingTheKey) {
    // 128 x 96 x (16 B colour target + 16 x 8 B entries) = 1.69 MiB over a 1 MB budget.
    writeScene(R"("transparency": "kbuffer", "kbuffer": {"k": 16}, "memory_budget_mb": 1)", 30, 128, 96);
    RunResult r = run("render scene.json");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("render.memory_budget_mb"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("k=16"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out" / "f.0000.png"));
    EXPECT_FALSE(fs::exists(dir / "out" / "f.0000.exr"));
    // Raising the budget on the command line renders the same scene (2 MB: 1.69 MiB fits).
    RunResult ok = run("render scene.json --set render.memory_budget_mb=2 -o ok");
    EXPECT_EQ(ok.code, 0) << ok.err;
    EXPECT_TRUE(fs::exists(dir / "ok" / "f.0000.exr"));
}

// style.halo is drawn by the transparent modes of rasterized, raytraced and voxel_raycast: the
// opaque modes refuse it with exit 2 naming the key and the technique, and so does a technique
// for particles; a bad value names the sub-key.
TEST_F(TransparencyCli, HaloIsRefusedByTechniquesThatDoNotDrawItAndAcceptedByTheTransparentModes) {
    writeScene(R"("technique": "rasterized", "transparency": "depth_peeling")", 8, 32, 24, 1.0f);
    for (const std::string technique : {"rasterized", "raytraced", "voxel_raycast"}) {
        RunResult ok = run("render scene.json --set style.halo.width=1 --set 'render.technique=\"" + technique +
                           "\"' -o " + technique);
        EXPECT_EQ(ok.code, 0) << technique << "\n" << ok.err;
        EXPECT_TRUE(fs::exists(dir / technique / "f.0000.exr")) << technique;
    }
    struct Refused {
        std::string set, expected;
    };
    for (const Refused& c : std::vector<Refused>{
             {"--set style.halo=true --set 'render.technique=\"voxel_raycast\"' --set 'render.transparency=\"opaque\"'",
              "style.halo: technique \"voxel_raycast\" draws halos with render.transparency \"object_order\", "
              "\"kbuffer\" or \"depth_peeling\", got \"opaque\""},
             {"--set style.halo=true --set 'render.transparency=\"opaque\"'",
              "style.halo: technique \"rasterized\" draws halos with render.transparency \"object_order\", "
              "\"kbuffer\", \"depth_peeling\" or \"opacity_optimization\", got \"opaque\""},
             {"--set style.halo=true --set 'render.technique=\"raytraced\"' --set 'render.transparency=\"opaque\"'",
              "style.halo: technique \"raytraced\" draws halos with render.transparency \"object_order\", "
              "\"kbuffer\" or \"depth_peeling\", got \"opaque\""},
             // A line style: refused for particles whatever the technique.
             {"--set style.halo=true --set 'dataset={\"generate\": \"droplets\", \"particles\": 200}' "
              "--set 'render.technique=\"raytraced\"'",
              "style.halo: halos are drawn around lines, the dataset holds particles"},
             {"--set style.halo.width=0", "style.halo.width: expected a number in (0, 100]"},
             {"--set style.halo.colour=[0,0,0]", "style.halo.colour"},
         }) {
        RunResult r = run("render scene.json " + c.set + " -o refused");
        EXPECT_EQ(r.code, 2) << c.set << "\n" << r.err;
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.set << "\n" << r.err;
    }
}

// `tubecast techniques` says which modes of which technique draw style.halo, as the refusals above.
TEST_F(TransparencyCli, TechniquesListTheModesThatDrawHalos) {
    RunResult r = run("techniques --json");
    ASSERT_EQ(r.code, 0) << r.err;
    std::map<std::string, std::vector<std::string>> halo;
    for (const nlohmann::json& t : nlohmann::json::parse(r.out)) halo[t.at("name")] = t.at("halo");
    const std::vector<std::string> exact = {"object_order", "kbuffer", "depth_peeling"};
    EXPECT_EQ(halo["rasterized"],
              (std::vector<std::string>{"object_order", "kbuffer", "depth_peeling", "opacity_optimization"}));
    EXPECT_EQ(halo["raytraced"], exact);
    EXPECT_EQ(halo["voxel_raycast"], exact);
    EXPECT_TRUE(halo["spheres"].empty());
    RunResult text = run("techniques");
    ASSERT_EQ(text.code, 0) << text.err;
    EXPECT_NE(text.out.find("  style.halo:   object_order, kbuffer, depth_peeling\n"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("  style.halo:   none\n"), std::string::npos) << text.out;
}

// Halos on opaque lines with the transparency left to "auto": the opaque paths draw no halos, so
// auto takes the technique's exact-order mode (rasterized: kbuffer; raytraced: depth_peeling,
// exact compositing), which with every opacity 1 composites to the nearest surface: the image
// equals the rasterized depth peeling's with the same halos.
TEST_F(TransparencyCli, HaloOnOpaqueLinesWithAutoPicksTheExactOrderModeAndEqualsDepthPeeling) {
    writeScene("", 8, 32, 24, 1.0f);
    const std::string halo = "--set style.halo.width=1 ";
    RunResult peel =
        run("render scene.json " + halo +
            "--set 'render.technique=\"rasterized\"' --set 'render.transparency=\"depth_peeling\"' -o peel");
    ASSERT_EQ(peel.code, 0) << peel.err;
    // Without halos the same auto scene stays opaque.
    RunResult plain = run("render scene.json -o plain");
    ASSERT_EQ(plain.code, 0) << plain.err;
    EXPECT_NE(plain.err.find("render.transparency auto: opaque"), std::string::npos) << plain.err;
    const std::string peelImage = (dir / "peel" / "f.0000.exr").string();
    struct Case {
        std::string technique, mode;
        float threshold;      // against rasterized depth peeling, any channel
        double fractionOver;  // of the pixels, the most that may differ by more
    };
    for (const Case& c : std::vector<Case>{
             // The k-buffer stores colours as RGBA8 (half a step of 1/255 of rounding), peeling as
             // floats; the same rays on the same rasterizer.
             {"rasterized", "kbuffer", 0.5f / 255.0f + 1e-6f, 0.0},
             // Exact compositing on the CPU: the same fragments up to float rounding; the pixels a
             // silhouette's or ring rim's ray decides the other way are counted below instead.
             {"raytraced", "depth_peeling", 1e-3f, 0.02},
         }) {
        SCOPED_TRACE(c.technique);
        RunResult r =
            run("render scene.json " + halo + "--set 'render.technique=\"" + c.technique + "\"' -o " + c.technique);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.err.find("render.transparency auto: " + c.mode), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("style.halo"), std::string::npos) << r.err;
        const std::string image = (dir / c.technique / "f.0000.exr").string();
        const tc::ImageDiff d = tc::compareImages(image, peelImage, c.threshold);
        std::printf("[ measured ] halos, %s against rasterized depth peeling: max %.3g, %.2f %% of px over %.3g\n",
                    c.technique.c_str(), d.maxError, 100.0 * d.fractionOver, double(c.threshold));
        EXPECT_LE(d.fractionOver, c.fractionOver) << "max " << d.maxError << ", PSNR " << d.psnr;
        const tc::ImageDiff shown = tc::compareImages(image, (dir / "plain" / "f.0000.exr").string(), 0.0f);
        EXPECT_GT(shown.maxError, 0.1) << "the halos must show";
    }
}

// Both backends run the same llvmpipe and the k-buffer's per-pixel order is deterministic there
// (llvmpipe bins by tile and one thread shades a tile's primitives in submission order): the
// images must agree exactly, AOVs included.
TEST_F(TransparencyCli, EglAndOsmesaRenderTheSameKbufferImage) {
    writeScene(R"("transparency": "kbuffer", "kbuffer": {"k": 4})", 60, 64, 48);
    RunResult egl = run("render scene.json --backend egl -o egl");
    ASSERT_EQ(egl.code, 0) << egl.err;
    RunResult osmesa = run("render scene.json --backend osmesa -o osmesa");
    ASSERT_EQ(osmesa.code, 0) << osmesa.err;
    const std::string a = (dir / "egl" / "f.0000.exr").string(), b = (dir / "osmesa" / "f.0000.exr").string();
    tc::ImageDiff d = tc::compareImages(a, b, 0.0f);
    EXPECT_EQ(d.maxError, 0.0);
    tc::FrameImages ia = tc::readExr(a), ib = tc::readExr(b);
    EXPECT_EQ(ia.rgba, ib.rgba);
    EXPECT_EQ(ia.depth, ib.depth);
    EXPECT_EQ(ia.normal, ib.normal);
    EXPECT_EQ(ia.id, ib.id);
    // Not vacuous: the image is transparent (some alpha strictly between 0 and 1).
    std::size_t partial = 0;
    for (std::size_t i = 3; i < ia.rgba.size(); i += 4) partial += ia.rgba[i] > 0.05f && ia.rgba[i] < 0.95f;
    EXPECT_GT(partial, 100u);
    const std::string runJson = readText(dir / "egl" / "run.json");
    EXPECT_NE(runJson.find("\"kbuffer\""), std::string::npos) << runJson;
}

std::vector<std::vector<std::string>> readCsv(const fs::path& p) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(readText(p));
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream ls(line);
        std::string cell;
        while (std::getline(ls, cell, ',')) cells.push_back(cell);
        rows.push_back(cells);
    }
    return rows;
}

// The k-buffer's quality target: the k-buffer with k = 8 within 40 dB PSNR of depth peeling. 120
// overlapping tornado streamlines at opacity 0.3 (moderately dense: the vortex core stacks
// dozens of layers) on a 2-frame orbit.
TEST_F(TransparencyCli, ReferenceDepthPeelingWritesQualityCsvWithPsnrOver40DbForKbuffer8) {
    writeScene(R"("transparency": "kbuffer", "kbuffer": {"k": 8}, "reference": "depth_peeling")", 120, 96, 72, 0.3f,
               R"(,
  "animation": {"type": "orbit", "frames": 2, "axis": [0, 0, 1], "degrees": 90})");
    RunResult r = run("render scene.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const fs::path quality = dir / "out" / "quality.csv";
    ASSERT_TRUE(fs::exists(quality));
    const auto rows = readCsv(quality);
    ASSERT_EQ(rows.size(), 3u) << readText(quality);  // header + one row per frame
    EXPECT_EQ(rows[0], (std::vector<std::string>{"frame", "reference", "rmse", "psnr_db", "max_error"}));
    for (int f = 0; f < 2; ++f) {
        const auto& row = rows[std::size_t(f) + 1];
        ASSERT_EQ(row.size(), 5u);
        EXPECT_EQ(row[0], std::to_string(f));
        EXPECT_EQ(row[1], "depth_peeling");
        const double rmse = std::stod(row[2]), psnr = std::stod(row[3]);
        std::printf("[ measured ] frame %d: k=8 vs depth peeling RMSE %.3g, PSNR %.1f dB, max error %s\n", f, rmse,
                    psnr, row[4].c_str());
        EXPECT_GT(rmse, 0.0) << "identical to the reference: the scene is not dense enough to test anything";
        EXPECT_GE(psnr, 40.0);
    }
    // The reference's cost is recorded per frame in timings.csv.
    EXPECT_NE(readText(dir / "out" / "timings.csv").find("\n1,reference,"), std::string::npos);
}

}  // namespace
