// The three places a billboard can be built (compute pre-pass, vertex shader, geometry shader)
// run the same shaders/billboard.glsl, so they must produce bit-identical images; only speed may
// differ (docs/performance.md).
#include <gtest/gtest.h>

#include "core/scene.h"
#include "core/technique.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc {
namespace {

class BillboardPaths : public test::GlTest {};

FrameImages renderWith(const StyledLines& lines, BillboardPath path, Transparency transparency) {
    Scene scene;
    scene.render.billboards = path;
    scene.render.transparency = transparency;
    scene.output.aovId = true;
    auto technique = gl::createTechnique(scene, lines);
    tc::FrameSetup setup;
    setup.camera.eye = {0.3f, 0.4f, 3.0f};
    setup.camera.target = {0.0f, 0.0f, 0.0f};
    setup.width = 96;
    setup.height = 72;
    gl::StageTimer timer;
    FrameImages out;
    technique->render(setup, out, timer);
    return out;
}

TEST_F(BillboardPaths, ComputeVertexAndGeometryPathsRenderIdenticalOpaqueImages) {
    StyledLines lines = test::randomLineScene(11);
    FrameImages compute = renderWith(lines, BillboardPath::Compute, Transparency::Opaque);
    for (BillboardPath path : {BillboardPath::Vertex, BillboardPath::Geometry}) {
        FrameImages other = renderWith(lines, path, Transparency::Opaque);
        EXPECT_EQ(compute.rgba, other.rgba);
        EXPECT_EQ(compute.depth, other.depth);
        EXPECT_EQ(compute.normal, other.normal);
        EXPECT_EQ(compute.id, other.id);
    }
    // The scene is not empty: the comparison above compares something.
    std::size_t covered = 0;
    for (auto id : compute.id) covered += id != kBackgroundId;
    EXPECT_GT(covered, compute.id.size() / 20);
}

TEST_F(BillboardPaths, ComputeAndGeometryPathsRenderIdenticalKBufferImages) {
    test::RandomSceneOptions options;
    options.polylines = 8;
    StyledLines lines = test::randomLineScene(12, options);
    for (auto& c : lines.color) c.w = 0.4f;
    FrameImages compute = renderWith(lines, BillboardPath::Compute, Transparency::KBuffer);
    FrameImages geometry = renderWith(lines, BillboardPath::Geometry, Transparency::KBuffer);
    EXPECT_EQ(compute.rgba, geometry.rgba);
}

}  // namespace
}  // namespace tc
