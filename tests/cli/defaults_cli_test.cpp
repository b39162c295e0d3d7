// What a user means, through the binary: a dataset alone renders with its default scene (and
// `tubecast scene` prints it), opacity below 1 means transparent, what the scene states wins over
// what the data implies, the log names what the dataset holds, PNG-only runs compute no AOVs,
// an empty tractogram renders the background, and "speed" follows the traced vector.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "io/image_io.h"

namespace fs = std::filesystem;

namespace {

using namespace tc::test;

using Track = std::vector<std::array<float, 3>>;

// An MRtrix .tck as MRtrix writes it: text header, Float32LE triplets, a NaN triplet after each
// track and an Inf triplet at the end. `count` is what the header claims.
void writeTck(const fs::path& path, const std::vector<Track>& tracks, long count) {
    // The data starts at a fixed offset after the header's END line (the bytes between are padding).
    std::string header = "mrtrix tracks\ndatatype: Float32LE\ncount: " + std::to_string(count) + "\nfile: . 128\nEND\n";
    header.resize(128, '\0');
    std::vector<float> data;
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (const Track& t : tracks) {
        for (const auto& p : t) data.insert(data.end(), p.begin(), p.end());
        data.insert(data.end(), {nan, nan, nan});
    }
    data.insert(data.end(), {inf, inf, inf});
    std::ofstream out(path, std::ios::binary);
    out << header;
    out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size() * sizeof(float)));
}

Track straight(std::array<float, 3> from, std::array<float, 3> to, int points = 20) {
    Track t;
    for (int i = 0; i < points; ++i) {
        const float s = float(i) / float(points - 1);
        t.push_back(
            {from[0] + s * (to[0] - from[0]), from[1] + s * (to[1] - from[1]), from[2] + s * (to[2] - from[2])});
    }
    return t;
}

// Pixels whose alpha is not 0, and of those the ones whose red or green channel dominates.
struct Coverage {
    std::size_t covered = 0, red = 0, green = 0;
};
Coverage coverage(const fs::path& png) {
    const tc::RgbaImage f = tc::readImageRgba(png.string());
    Coverage c;
    for (std::size_t i = 0; i < std::size_t(f.width) * std::size_t(f.height); ++i) {
        const float* p = &f.rgba[4 * i];
        if (p[3] <= 0.0f) continue;
        ++c.covered;
        c.red += p[0] > 2.0f * p[1] && p[0] > 2.0f * p[2];
        c.green += p[1] > 2.0f * p[0] && p[1] > 2.0f * p[2];
    }
    return c;
}

class Defaults : public CliFixture {
protected:
    // Two tracts: one along x, one along y (the default view looks down -z).
    void writeFibers() {
        writeTck(dir / "fibers.tck",
                 {straight({-1, 0.5f, 0}, {1, 0.5f, 0}), straight({0.5f, -1, 0.2f}, {0.5f, 1, 0.2f})}, 2);
    }
};

TEST_F(Defaults, a_tractogram_alone_renders_fitted_and_direction_coloured) {
    writeFibers();
    // 256 pixels: the default radius (0.2 % of the diagonal) is then about one pixel wide.
    RunResult r = run("render fibers.tck -o out --set image.width=256 --set image.height=256");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("2 polylines, 38 segments"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("colour: direction-encoded"), std::string::npos) << r.err;
    ASSERT_TRUE(fs::exists(dir / "out" / "fibers.png")) << "the output is named after the dataset";
    const Coverage c = coverage(dir / "out" / "fibers.png");
    EXPECT_GT(c.covered, 96u) << "both tracts are in view";
    EXPECT_GT(c.red, 20u) << "the tract along x is red";
    EXPECT_GT(c.green, 20u) << "the tract along y is green";
    // The camera looks at the middle of the data (camera.fit).
    const auto run = nlohmann::json::parse(readText(dir / "out" / "run.json"));
    const auto target = run["camera_first_frame"]["target"];
    EXPECT_NEAR(target[0].get<double>(), 0.0, 0.05);
    EXPECT_NEAR(target[1].get<double>(), 0.0, 0.05);
}

TEST_F(Defaults, scene_prints_the_default_scene_and_rendering_it_gives_the_same_image) {
    writeFibers();
    RunResult s = run("scene fibers.tck");
    ASSERT_EQ(s.code, 0) << s.err;
    const auto scene = nlohmann::json::parse(s.out);
    EXPECT_EQ(scene["dataset"]["path"], "fibers.tck");
    EXPECT_EQ(scene["style"]["color"], "direction");
    // 0.2 % of the bounding-box diagonal of the vertices: (2, 2, 0.2).
    EXPECT_NEAR(scene["style"]["radius"].get<double>(), 0.002 * std::sqrt(8.04), 1e-6);
    writeText(dir / "fibers.json", s.out);
    ASSERT_EQ(run("render fibers.tck -o a --set image.width=64 --set image.height=64").code, 0);
    ASSERT_EQ(run("render fibers.json -o b --set image.width=64 --set image.height=64").code, 0);
    EXPECT_EQ(readText(dir / "a" / "fibers.png"), readText(dir / "b" / "fibers.png"));
    EXPECT_EQ(run("scene nothing.json").code, 2);
}

TEST_F(Defaults, opacity_below_one_is_transparent_unless_the_scene_says_opaque) {
    writeFibers();
    RunResult r =
        run("render fibers.tck -o out --set image.width=48 --set image.height=48 --set style.opacity=0.3 "
            "--set render.technique=rasterized");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("render.transparency auto: kbuffer"), std::string::npos) << r.err;
    auto run1 = nlohmann::json::parse(readText(dir / "out" / "run.json"));
    EXPECT_EQ(run1["technique"]["transparency"], "kbuffer");
    EXPECT_NE(run1["technique_choice"].get<std::string>().find("opacity below 1"), std::string::npos);

    r =
        run("render fibers.tck -o opaque --set image.width=48 --set image.height=48 --set style.opacity=0.3 "
            "--set render.technique=rasterized --set render.transparency=opaque");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("warning: fibers.tck: render.transparency: \"opaque\" draws every opacity below 1 as 1"),
              std::string::npos)
        << r.err;
    r = run("render fibers.tck -o one --set image.width=48 --set image.height=48 --set render.technique=rasterized");
    EXPECT_NE(r.err.find("render.transparency auto: opaque (every opacity is 1)"), std::string::npos) << r.err;
}

// 343 carbon atoms on a lattice in the unit cube: element radii (1.7 Angstrom) cover everything.
void writeCarbon(const fs::path& path) {
    std::string text = "343\ncarbon lattice\n";
    for (int i = 0; i < 7; ++i)
        for (int j = 0; j < 7; ++j)
            for (int k = 0; k < 7; ++k)
                text += "C " + std::to_string(i / 6.0) + " " + std::to_string(j / 6.0) + " " + std::to_string(k / 6.0) +
                        "\n";
    writeText(path, text);
}

TEST_F(Defaults, a_radius_the_scene_states_wins_over_element_radii) {
    writeCarbon(dir / "carbon.xyz");
    RunResult implied = run("render carbon.xyz -o implied --set image.width=64 --set image.height=64");
    ASSERT_EQ(implied.code, 0) << implied.err;
    EXPECT_NE(implied.err.find("343 particles"), std::string::npos) << implied.err;
    EXPECT_NE(implied.err.find("radius: element radii (C 1.7)"), std::string::npos) << implied.err;
    EXPECT_NE(implied.err.find("colour: element colours (CPK)"), std::string::npos) << implied.err;

    writeText(dir / "scene.json", R"({"dataset": {"path": "carbon.xyz"}, "style": {"radius": 0.01},
        "image": {"width": 64, "height": 64}, "output": {"dir": "stated", "name": "f"}})");
    RunResult stated = run("render scene.json");
    ASSERT_EQ(stated.code, 0) << stated.err;
    EXPECT_NE(stated.err.find("radius: constant 0.01 from the scene"), std::string::npos) << stated.err;
    // The camera fits the spheres either way: spheres of 0.01 in a unit cube cover about 2 % of
    // the pixels; 1.7 Angstrom spheres merge into one rounded block of 4.4 units, about 28 % of the
    // fitted view (its bounding sphere, radius 3.8).
    const std::size_t small = coverage(dir / "stated" / "f.png").covered;
    const std::size_t large = coverage(dir / "implied" / "carbon.png").covered;
    EXPECT_LT(small, 64u * 64u / 10) << small;
    EXPECT_GT(large, 64u * 64u / 5) << large;
}

TEST_F(Defaults, png_only_runs_compute_no_aovs_and_a_listed_aov_is_warned_about) {
    writeFibers();
    const std::string common =
        "--set image.width=48 --set image.height=48 --set style.opacity=0.5 "
        "--set render.technique=rasterized --set render.transparency=kbuffer";
    RunResult both = run("render fibers.tck -o both " + common);
    ASSERT_EQ(both.code, 0) << both.err;
    EXPECT_NE(readText(dir / "both" / "timings.csv").find(",gbuffer,"), std::string::npos);
    RunResult png = run("render fibers.tck -o png " + common + " --set 'output.formats=[\"png\"]'");
    ASSERT_EQ(png.code, 0) << png.err;
    EXPECT_EQ(readText(dir / "png" / "timings.csv").find(",gbuffer,"), std::string::npos);
    EXPECT_EQ(png.err.find("warning"), std::string::npos) << "the default AOVs are not the user's" << png.err;
    RunResult listed = run("render fibers.tck -o listed " + common +
                           " --set 'output.formats=[\"png\"]' --set 'output.aovs=[\"depth\",\"id\"]'");
    ASSERT_EQ(listed.code, 0) << listed.err;
    EXPECT_NE(listed.err.find("warning: fibers.tck: output.aovs: only EXR files hold AOVs"), std::string::npos)
        << listed.err;
    EXPECT_EQ(readText(dir / "listed" / "timings.csv").find(",gbuffer,"), std::string::npos);
}

TEST_F(Defaults, auto_picks_the_cpu_ray_tracer_on_a_software_rasterizer_and_says_so) {
    writeFibers();
    RunResult r = run("render fibers.tck -o out --set image.width=32 --set image.height=32");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto run1 = nlohmann::json::parse(readText(dir / "out" / "run.json"));
    const std::string renderer = run1["gl"]["renderer"];
    if (renderer.find("llvmpipe") == std::string::npos) GTEST_SKIP() << "not on llvmpipe: " << renderer;
    EXPECT_NE(r.err.find("render.technique auto: raytraced (GL renderer"), std::string::npos) << r.err;
    EXPECT_EQ(run1["technique"]["technique"], "raytraced");
    EXPECT_NE(run1["technique_choice"].get<std::string>().find("software rasterizer"), std::string::npos);
}

TEST_F(Defaults, an_empty_tractogram_renders_the_background_with_a_warning) {
    writeTck(dir / "empty.tck", {}, 0);
    RunResult r = run("render empty.tck -o out --set image.width=16 --set image.height=16");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("warning: empty.tck: the dataset holds no polylines"), std::string::npos) << r.err;
    EXPECT_EQ(coverage(dir / "out" / "empty.png").covered, 0u);
    RunResult info = run("info empty.tck --json");
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_EQ(nlohmann::json::parse(info.out)["polylines"], 0);
}

TEST_F(Defaults, speed_is_the_magnitude_of_the_traced_vector_whatever_its_name) {
    // A uniform field V = (3, 4, 0): |V| = 5 everywhere.
    writeUniformVti(dir / "field.vti", "V", "3 4 0");
    writeText(dir / "scene.json", R"({"dataset": {"path": "field.vti",
        "trace": {"vector": "V", "seeding": "line", "seeds": 3, "line": [[0.2, 0.2, 0.5], [0.2, 0.4, 0.5]]}},
        "style": {"color": {"attribute": "speed"}}})");
    RunResult r = run("info scene.json --json");
    ASSERT_EQ(r.code, 0) << r.err;
    bool found = false;
    const auto info = nlohmann::json::parse(r.out);  // named: a temporary would die before the loop
    for (const auto& a : info["attributes"])
        if (a["name"] == "speed") {
            found = true;
            EXPECT_NEAR(a["min"].get<double>(), 5.0, 1e-4);
            EXPECT_NEAR(a["max"].get<double>(), 5.0, 1e-4);
        }
    EXPECT_TRUE(found) << r.out;
}

}  // namespace
