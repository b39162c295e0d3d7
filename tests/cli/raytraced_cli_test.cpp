// render.technique "raytraced" / "auto" through the tubecast binary: outputs and run.json, the GL
// depth peeling as reference for the exact ray-traced transparency (quality.csv), auto's choice on
// llvmpipe, and the ray-traced AO method rejected for the rasterized technique.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "io/image_io.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

class RaytracedCli : public CliFixture {
protected:
    fs::path writeScene(const std::string& render, int width = 48, int height = 36, float opacity = 1.0f) {
        std::ostringstream text;
        text << R"({
  "dataset": {"generate": "tornado", "lines": 30, "points": 40, "seed": 3},
  "style": {"radius": 0.02, "color": {"attribute": "speed", "colormap": "viridis"}, "opacity": )"
             << opacity << R"(},
  "camera": {"fit": true, "eye": [1.6, -1.2, 1.25], "target": [0.5, 0.5, 0.5], "up": [0, 0, 1], "fov_deg": 30},
  "image": {"width": )"
             << width << R"(, "height": )" << height << R"(},
  "render": {)" << render
             << R"(},
  "output": {"dir": "out", "name": "f.####", "aovs": ["depth", "normal", "id"]}
}
)";
        writeText(dir / "scene.json", text.str());
        return dir / "scene.json";
    }
};

TEST_F(RaytracedCli, RaytracedRenderWritesImagesAndDescribesTheBvh) {
    writeScene(R"("technique": "raytraced")");
    RunResult r = run("render scene.json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out" / "f.0000.png"));
    ASSERT_TRUE(fs::exists(dir / "out" / "f.0000.exr"));
    tc::FrameImages img = tc::readExr((dir / "out" / "f.0000.exr").string());
    int covered = 0;
    for (std::size_t i = 0; i < img.pixelCount(); ++i) covered += std::isfinite(img.depth[i]);
    EXPECT_GT(covered, 50);
    nlohmann::json run = nlohmann::json::parse(readText(dir / "out" / "run.json"));
    EXPECT_EQ(run["technique"]["technique"], "raytraced");
    EXPECT_GT(run["technique"]["bvh_build_ms"].get<double>(), 0.0);
    EXPECT_GT(run["technique"]["bvh_memory_mb"].get<double>(), 0.0);
    EXPECT_NE(readText(dir / "out" / "timings.csv").find("\n0,raytrace,"), std::string::npos);
}

TEST_F(RaytracedCli, ExactRaytracedTransparencyMatchesGlDepthPeelingInQualityCsv) {
    writeScene(R"("technique": "raytraced", "transparency": "depth_peeling", "raytraced": {"alpha_cutoff": 1.0},
                  "reference": "depth_peeling")",
               64, 48, 0.3f);
    RunResult r = run("render scene.json");
    ASSERT_EQ(r.code, 0) << r.err;
    std::string quality = readText(dir / "out" / "quality.csv");
    std::istringstream lines(quality);
    std::string header, row;
    std::getline(lines, header);
    std::getline(lines, row);
    ASSERT_EQ(header, "frame,reference,rmse,psnr_db,max_error");
    std::vector<std::string> f;
    std::stringstream cells(row);
    for (std::string c; std::getline(cells, c, ',');) f.push_back(c);
    ASSERT_EQ(f.size(), 5u) << quality;
    EXPECT_EQ(f[1], "depth_peeling");
    const double psnr = std::stod(f[3]);
    std::printf("[ measured ] raytraced exact vs GL depth peeling: PSNR %.1f dB, max error %s\n", psnr, f[4].c_str());
    EXPECT_GE(psnr, 40.0);
}

TEST_F(RaytracedCli, AutoPicksRaytracedOnLlvmpipeAndSaysSo) {
    writeScene(R"("technique": "auto", "reference": "raytraced")");
    RunResult r = run("render scene.json");
    ASSERT_EQ(r.code, 0) << r.err;
    nlohmann::json run = nlohmann::json::parse(readText(dir / "out" / "run.json"));
    const std::string renderer = run["gl"]["renderer"];
    if (renderer.find("llvmpipe") == std::string::npos) GTEST_SKIP() << "not on llvmpipe: " << renderer;
    EXPECT_NE(r.err.find("render.technique auto: raytraced"), std::string::npos) << r.err;
    EXPECT_EQ(run["technique"]["technique"], "raytraced");
    // The ray-traced reference of a ray-traced opaque frame is the same image.
    std::string quality = readText(dir / "out" / "quality.csv");
    EXPECT_NE(quality.find("\n0,raytraced,0,inf,0"), std::string::npos) << quality;
}

TEST_F(RaytracedCli, RayTracedAoWithTheRasterizedTechniqueIsExit2) {
    writeScene(R"("technique": "rasterized", "ao": {"method": "ray_traced"})");
    RunResult r = run("render scene.json");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("render.ao.method"), std::string::npos) << r.err;
}

}  // namespace

// Particles (rt/raytraced_particles.h): the opaque ray-traced frame against the GL sphere glyphs
// of the same scene (both: first sphere hit, Blinn-Phong), and AO rejected.
TEST_F(RaytracedCli, RaytracedParticlesMatchTheGlSpheresOpaqueAndRejectAo) {
    auto scene = [&](const std::string& technique, const std::string& extra) {
        writeText(dir / "drops.json", R"({
  "dataset": {"generate": "droplets", "particles": 3000, "seed": 2},
  "style": {"color": {"attribute": "density", "colormap": "viridis", "range": [0.0, 1.6]}, "opacity": 0.5},
  "camera": {"fit": true, "eye": [0.5, -1.2, 1.4], "target": [0.5, 0.5, 0.5], "up": [0, 0, 1], "fov_deg": 35},
  "image": {"width": 64, "height": 48, "background": [0, 0, 0, 1]},
  "render": {"technique": ")" + technique + R"(", "transparency": "opaque")" + extra + R"(},
  "output": {"dir": "out_)" + technique + R"(", "name": "p", "formats": ["png"], "aovs": []}
})");
    };
    scene("raytraced", "");
    RunResult r = run("render drops.json");
    ASSERT_EQ(r.code, 0) << r.err;
    nlohmann::json run = nlohmann::json::parse(readText(dir / "out_raytraced" / "run.json"));
    EXPECT_EQ(run["technique"]["geometry"], "RTC_GEOMETRY_TYPE_SPHERE_POINT");
    scene("spheres", "");
    r = this->run("render drops.json");
    ASSERT_EQ(r.code, 0) << r.err;
    // 8-bit PNGs: the same spheres and shading (measured: PSNR 83 dB, no pixel over 3/255); the
    // allowance is for silhouette pixels decided differently by the two intersection codes.
    tc::ImageDiff d = tc::compareImages((dir / "out_raytraced" / "p.png").string(), (dir / "out_spheres" / "p.png").string(),
                                        3.0f / 255.0f);
    EXPECT_LT(d.fractionOver, 0.01) << d.fractionOver;
    EXPECT_GT(d.psnr, 50.0) << d.psnr;
    std::cout << "raytraced vs GL spheres, opaque: PSNR " << d.psnr << " dB, " << 100.0 * d.fractionOver
              << " % of pixels over 3/255\n";

    scene("raytraced", R"(, "ao": {"enabled": true})");
    r = this->run("render drops.json --overwrite");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("render.ao.enabled"), std::string::npos) << r.err;
}
