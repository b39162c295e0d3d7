#pragma once
// Shared golden-image helpers of the GL tests (golden_test.cpp, transparency_golden_test.cpp,
// ambient_occlusion_test.cpp): rendering a scene as `tubecast render` does, and comparing a frame
// with a reviewed image in tests/golden/, or overwriting it when TUBECAST_BLESS=1
// (scripts/bless-goldens.sh; tests/golden/README.md says when and how).
#include <string>

#include "core/frame_images.h"
#include "core/scene.h"
#include "io/image_io.h"

namespace tc::test {

// Thresholds, on 8-bit values read back as v / 255 (RGBA, straight alpha):
// - a pixel "differs" when any channel differs by more than 2/255 (2 levels): the image is
//   shaded in float and rounded once to 8 bits, so a different Mesa/LLVM (other fma contraction,
//   other pow/rsqrt approximations) moves values across a rounding boundary by 1 level, rarely 2;
// - at most 0.5 % of the pixels may differ: grazing pixels on tube silhouettes can flip between
//   tube and background (a full-range difference) when the intersector's last bits change; the
//   demo has a few thousand silhouette pixels at this size, a regression (wrong colormap, camera,
//   light, missing tubes) changes far more;
// - the mean absolute difference over all RGBA values must stay below 1e-3 (~1/4 level): a
//   global shift of one level (a changed sRGB encode or lighting term) fails it even if no single
//   pixel is over the threshold.
// llvmpipe on the development machine reproduces the goldens exactly (measured: 0 differing
// values), so these margins are only for other Mesa versions.
inline constexpr float kPixelThreshold = 2.5f / 255.0f;  // > 2 levels (values are multiples of 1/255)
inline constexpr double kMaxFractionOver = 0.005;
inline constexpr double kMaxMeanError = 1e-3;

// TUBECAST_SOURCE_DIR / relative.
std::string sourcePath(const std::string& relative);

// True when TUBECAST_BLESS=1: goldens are overwritten instead of compared.
bool blessing();

// Mean absolute difference over all RGBA values of two images of the same size (0 when empty).
double meanAbsoluteDifference(const RgbaImage& a, const RgbaImage& b);

// Renders frame 0 of a scene as cli/render.cpp does, composited over the scene's background.
FrameImages renderSceneFrame(const Scene& scene);

// Compares `images` with tests/golden/<name>.png (kPixelThreshold, kMaxFractionOver,
// kMaxMeanError), writing <name>.actual.png and, on a mismatch, <name>.diff.png under
// TUBECAST_TEST_TMP/golden; or overwrites the golden when blessing.
void expectMatchesGolden(const FrameImages& images, const std::string& name);

}  // namespace tc::test
