// Golden image of a transparent scene: the k-buffer (k = 8, cap clipping) rendered the way
// `tubecast render` renders it (scene parser, dataset generator, styling with opacity, fitted
// camera, technique, background composite, 8-bit sRGB PNG), compared with a reviewed image in
// tests/golden/ with the thresholds and bless mechanism of golden_test.cpp (TUBECAST_BLESS=1,
// scripts/bless-goldens.sh; tests/golden/README.md). The per-pixel correctness of the transparent
// paths is tested against depth peeling and the CPU reference in transparency_test.cpp; this
// catches end-to-end regressions (opacity styling, sort, k-buffer resolve, compositing).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/scene.h"
#include "gl_fixture.h"
#include "golden.h"
#include "io/json_file.h"

namespace tc::test {
namespace {

// The thresholds of golden_test.cpp (shared in golden.h; see there and tests/golden/README.md for
// the reasoning): a pixel differs when a channel is more than 2/255 off, at most 0.5 % may differ,
// mean absolute difference <= 1e-3. The k-buffer adds no nondeterminism on llvmpipe (per-pixel order is the
// primitive order; EGL and OSMesa agree exactly, tests/cli/transparency_cli_test.cpp), and its
// RGBA8 entries are rounded once, like the PNG; so the same margins apply.

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
