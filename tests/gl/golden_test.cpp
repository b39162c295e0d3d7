// Golden images: whole scenes rendered the way `tubecast render` renders them (scene parser with
// --set-style overrides, dataset generator, styling, fitted camera, technique, background
// composite, 8-bit sRGB PNG), compared with reviewed images in tests/golden/. The per-pixel
// correctness of the technique is tested against the CPU reference in
// rounded_cone_renderer_test.cpp; these catch end-to-end regressions (styling, colormaps, camera
// fit, lighting, compositing, PNG encoding) that the analytic tests do not see.
//
// TUBECAST_BLESS=1 writes the rendered images over the goldens instead of comparing
// (scripts/bless-goldens.sh; tests/golden/README.md says when and how). The thresholds and the
// comparison are in golden.h / golden.cpp, shared with the other golden tests.
#include "golden.h"

#include <gtest/gtest.h>

#include <string>

#include "core/scene.h"
#include "gl_fixture.h"
#include "io/json_file.h"

namespace tc::test {
namespace {

using GoldenTest = GlTest;

TEST_F(GoldenTest, demo_scene_at_256x192_matches_golden) {
    const std::string file = sourcePath("configs/demo.json");
    const Scene scene = parseScene(readJsonFile(file), file, {"image.width=256", "image.height=192"});
    ASSERT_EQ(scene.image.width, 256);
    ASSERT_EQ(scene.image.height, 192);
    expectMatchesGolden(renderSceneFrame(scene), "demo_256x192");
}

TEST_F(GoldenTest, orthographic_attribute_radius_on_light_background_matches_golden) {
    const std::string file = sourcePath("tests/golden/ortho_radius_by_speed.json");
    const Scene scene = parseScene(readJsonFile(file), file);
    ASSERT_EQ(scene.camera.camera.projection, Projection::Orthographic);
    ASSERT_FALSE(scene.style.radius.attribute.empty());
    expectMatchesGolden(renderSceneFrame(scene), "ortho_radius_by_speed_192");
}

}  // namespace
}  // namespace tc::test
