// Golden image of a transparent scene: the k-buffer (k = 8, cap clipping) rendered the way
// `tubecast render` renders it (scene parser, dataset generator, styling with opacity, fitted
// camera, technique, background composite, 8-bit sRGB PNG), compared with a reviewed image in
// tests/golden/ with the thresholds and bless mechanism of golden_test.cpp (TUBECAST_BLESS=1,
// scripts/bless-goldens.sh; tests/golden/README.md). The per-pixel correctness of the transparent
// paths is tested against depth peeling and the CPU reference in transparency_test.cpp; this
// catches end-to-end regressions (opacity styling, sort, k-buffer resolve, compositing).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/animation.h"
#include "core/compositing.h"
#include "core/scene.h"
#include "core/styling.h"
#include "gl/gpu_timer.h"
#include "gl/technique.h"
#include "gl_fixture.h"
#include "io/dataset.h"
#include "io/image_io.h"
#include "io/json_file.h"

namespace tc::test {
namespace {

namespace fs = std::filesystem;

// The thresholds of golden_test.cpp (see there and tests/golden/README.md for the reasoning): a
// pixel differs when a channel is more than 2/255 off, at most 0.5 % may differ, mean absolute
// difference <= 1e-3. The k-buffer adds no nondeterminism on llvmpipe (per-pixel order is the
// primitive order; EGL and OSMesa agree exactly, tests/cli/transparency_cli_test.cpp), and its
// RGBA8 entries are rounded once, like the PNG; so the same margins apply.
constexpr float kPixelThreshold = 2.5f / 255.0f;
constexpr double kMaxFractionOver = 0.005;
constexpr double kMaxMeanError = 1e-3;

std::string sourcePath(const std::string& relative) { return (fs::path(TUBECAST_SOURCE_DIR) / relative).string(); }

bool blessing() {
    const char* v = std::getenv("TUBECAST_BLESS");
    return v && std::string(v) == "1";
}

FrameImages renderSceneFrame(const Scene& scene) {
    const DatasetLoad data = loadDataset(scene.dataset);
    const StyledLines styled = styleLines(data.lines, scene.style, scene.file);
    auto technique = gl::createTechnique(scene, styled);
    const float aspect = float(scene.image.width) / float(scene.image.height);
    const Camera camera = cameraAtFrame(scene.animation, fitCamera(scene.camera, styled.bounds, aspect), 0);
    gl::StageTimer timer;
    FrameImages images;
    technique->render(gl::FrameSetup{0, camera, scene.image.width, scene.image.height}, images, timer);
    timer.collect();
    compositeUnder(images, scene.image.background);
    return images;
}

void writeDiffImage(const RgbaImage& a, const RgbaImage& b, const std::string& path) {
    FrameImages diff;
    diff.allocate(a.width, a.height);
    for (std::size_t i = 0; i < diff.pixelCount(); ++i) {
        float alphaDiff = std::abs(a.rgba[4 * i + 3] - b.rgba[4 * i + 3]);
        for (int c = 0; c < 3; ++c)
            diff.rgba[4 * i + c] = std::min(1.0f, 8.0f * std::max(std::abs(a.rgba[4 * i + c] - b.rgba[4 * i + c]), alphaDiff));
        diff.rgba[4 * i + 3] = 1.0f;
    }
    writePng(diff, path);
}

void expectMatchesGolden(const FrameImages& images, const std::string& name) {
    const std::string golden = sourcePath("tests/golden/" + name + ".png");
    if (blessing()) {
        writePng(images, golden);
        std::printf("[ blessed  ] %s\n", golden.c_str());
        return;
    }
    const fs::path outDir = fs::path(TUBECAST_TEST_TMP) / "golden";
    fs::create_directories(outDir);
    const std::string actual = (outDir / (name + ".actual.png")).string();
    const std::string diffPath = (outDir / (name + ".diff.png")).string();
    writePng(images, actual);
    ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; render it with scripts/bless-goldens.sh and review it. "
                                    << "Actual image: " << actual;
    const ImageDiff d = compareImages(actual, golden, kPixelThreshold);
    const RgbaImage a = readImageRgba(actual), g = readImageRgba(golden);
    double sum = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) sum += std::abs(double(a.rgba[i]) - double(g.rgba[i]));
    const double mean = a.rgba.empty() ? 0.0 : sum / double(a.rgba.size());
    std::printf("[ measured ] golden %s: %zu px, max error %.4f (%.1f/255), pixels over 2/255 %.4f %%, mean %.3g, "
                "PSNR %.1f dB\n",
                name.c_str(), d.pixels, d.maxError, d.maxError * 255.0, 100.0 * d.fractionOver, mean, d.psnr);
    const bool ok = d.fractionOver <= kMaxFractionOver && mean <= kMaxMeanError;
    if (!ok) writeDiffImage(a, g, diffPath);
    EXPECT_LE(d.fractionOver, kMaxFractionOver) << "pixels differing by more than 2/255";
    EXPECT_LE(mean, kMaxMeanError) << "mean absolute difference";
    if (!ok)
        ADD_FAILURE() << "golden mismatch for " << name << "\n  golden: " << golden << "\n  actual: " << actual
                      << "\n  diff (8x): " << diffPath
                      << "\n  if the change is intended and reviewed, re-bless with scripts/bless-goldens.sh";
}

using TransparencyGoldenTest = GlTest;

TEST_F(TransparencyGoldenTest, kbuffer_opacity_0_3_with_cap_clipping_matches_golden) {
    const std::string file = sourcePath("tests/golden/transparent_kbuffer.json");
    const Scene scene = parseScene(readJsonFile(file), file);
    ASSERT_EQ(scene.render.transparency, Transparency::KBuffer);
    ASSERT_EQ(scene.render.kbufferK, 8);
    ASSERT_TRUE(scene.render.capClipping);
    ASSERT_FLOAT_EQ(scene.style.opacity.constant, 0.3f);
    ASSERT_LE(std::max(scene.image.width, scene.image.height), 256);
    expectMatchesGolden(renderSceneFrame(scene), "transparent_kbuffer_192x144");
}

}  // namespace
}  // namespace tc::test
