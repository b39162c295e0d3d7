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

FrameImages renderWith(const StyledLines& lines, BillboardPath path, Transparency transparency,
                       BillboardShape shape = BillboardShape::Gross2020) {
    Scene scene;
    scene.render.billboards = path;
    scene.render.billboardShape = shape;
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

// Both billboard shapes contain every cone's silhouette (tests/unit/billboard_test.cpp), and a
// pixel's colour does not depend on which quad produced its fragment: the images are identical,
// on every path. A shape that cut a silhouette would lose pixels here.
TEST_F(BillboardPaths, Gross2020AndRectangleBillboardsRenderIdenticalImagesOnEveryPath) {
    test::RandomSceneOptions options;
    options.polylines = 8;
    StyledLines lines = test::randomLineScene(13, options);
    for (BillboardPath path : {BillboardPath::Compute, BillboardPath::Vertex, BillboardPath::Geometry}) {
        FrameImages paper = renderWith(lines, path, Transparency::Opaque, BillboardShape::Gross2020);
        FrameImages rectangle = renderWith(lines, path, Transparency::Opaque, BillboardShape::Rectangle);
        EXPECT_EQ(paper.rgba, rectangle.rgba);
        EXPECT_EQ(paper.depth, rectangle.depth);
        EXPECT_EQ(paper.id, rectangle.id);
        std::size_t covered = 0;
        for (auto id : paper.id) covered += id != kBackgroundId;
        EXPECT_GT(covered, paper.id.size() / 20);
    }
    for (auto& c : lines.color) c.w = 0.4f;
    EXPECT_EQ(renderWith(lines, BillboardPath::Compute, Transparency::KBuffer, BillboardShape::Gross2020).rgba,
              renderWith(lines, BillboardPath::Compute, Transparency::KBuffer, BillboardShape::Rectangle).rgba);
}

}  // namespace
}  // namespace tc
