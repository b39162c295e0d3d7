#include "golden.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "core/animation.h"
#include "core/compositing.h"
#include "core/styling.h"
#include "core/technique.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "io/dataset.h"

namespace tc::test {
namespace {

namespace fs = std::filesystem;

// |a - b| per channel, amplified 8x so one-level differences are visible, alpha 1. writePng then
// sRGB-encodes it, which brightens small values further.
void writeDiffImage(const RgbaImage& a, const RgbaImage& b, const std::string& path) {
    FrameImages diff;
    diff.allocate(a.width, a.height);
    for (std::size_t i = 0; i < diff.pixelCount(); ++i) {
        float alphaDiff = std::abs(a.rgba[4 * i + 3] - b.rgba[4 * i + 3]);
        for (int c = 0; c < 3; ++c)
            diff.rgba[4 * i + c] =
                std::min(1.0f, 8.0f * std::max(std::abs(a.rgba[4 * i + c] - b.rgba[4 * i + c]), alphaDiff));
        diff.rgba[4 * i + 3] = 1.0f;
    }
    writePng(diff, path);
}

}  // namespace

std::string sourcePath(const std::string& relative) {
    return (fs::path(TUBECAST_SOURCE_DIR) / relative).string();
}

bool blessing() {
    const char* v = std::getenv("TUBECAST_BLESS");
    return v && std::string(v) == "1";
}

double meanAbsoluteDifference(const RgbaImage& a, const RgbaImage& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) sum += std::abs(double(a.rgba[i]) - double(b.rgba[i]));
    return a.rgba.empty() ? 0.0 : sum / double(a.rgba.size());
}

FrameImages renderSceneFrame(const Scene& scene) {
    const DatasetLoad data = loadDataset(scene.dataset);
    const StyledLines styled = styleLines(data.lines, scene.style, scene.file);
    auto technique = gl::createTechnique(scene, styled);
    const float aspect = float(scene.image.width) / float(scene.image.height);
    const Camera camera = cameraAtFrame(scene.animation, fitCamera(scene.camera, styled.bounds, aspect), 0);
    gl::StageTimer timer;
    FrameImages images;
    technique->render(tc::FrameSetup{0, camera, scene.image.width, scene.image.height}, images, timer);
    timer.collect();
    compositeUnder(images, scene.image.background);
    return images;
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

    const RgbaImage a = readImageRgba(actual), g = readImageRgba(golden);
    ASSERT_EQ(a.rgba.size(), g.rgba.size()) << "image size differs from the golden's; actual: " << actual;
    const ImageDiff d = compareImages(actual, golden, kPixelThreshold);
    // Mean absolute error ourselves: ImageDiff carries RMSE, the mean is the threshold stated above.
    const double mean = meanAbsoluteDifference(a, g);
    std::printf(
        "[ measured ] golden %s: %zu px, max error %.4f (%.1f/255), pixels over 2/255 %.4f %%, mean %.3g, "
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

}  // namespace tc::test
