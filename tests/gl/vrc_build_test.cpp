// Where the voxel ray caster's model is built (render.vrc.build; gl/vrc_renderer.h): the GPU
// build and the CPU build give the same image, and run.json says which one ran.
#include <gtest/gtest.h>

#include <memory>

#include "core/scene.h"
#include "core/technique.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

TEST_F(GlTest, vrc_gpu_built_model_renders_the_cpu_built_image) {
    RandomSceneOptions o;
    o.polylines = 60;
    const StyledLines lines = randomLineScene(5, o);
    Camera cam;
    cam.eye = {0.4f, 0.6f, 3.0f};
    FrameImages images[2];
    for (int k = 0; k < 2; ++k) {
        Scene scene;
        scene.image.width = 64;
        scene.image.height = 48;
        scene.render.technique = RenderTechnique::VoxelRaycast;
        scene.render.transparency = Transparency::KBuffer;
        scene.render.vrc.resolution = 24;
        scene.render.vrc.build = k == 0 ? VrcSpec::Build::Cpu : VrcSpec::Build::Gpu;
        std::unique_ptr<Technique> t = gl::createTechnique(scene, lines);
        EXPECT_EQ(t->describe()["build"], k == 0 ? "cpu" : "gpu");
        gl::StageTimer timer;
        t->render(FrameSetup{0, cam, scene.image.width, scene.image.height}, images[k], timer);
        timer.collect();
    }
    ASSERT_FALSE(images[0].rgba.empty());
    EXPECT_EQ(images[0].rgba, images[1].rgba);
    EXPECT_EQ(images[0].id, images[1].id);
}

}  // namespace
}  // namespace tc::test
