// Where the voxel ray caster's model is built (render.vrc.build; gl/vrc_renderer.h): the GPU
// build and the CPU build give the same image, run.json says which one ran, and "auto" builds on
// the GPU except on a software rasterizer.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "core/scene.h"
#include "core/technique.h"
#include "core/technique_registry.h"
#include "gl/gl_api.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl/vrc_renderer.h"
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
        Scene scene = vrcScene(64, 48, 24, Transparency::KBuffer);
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

TEST(VrcBuild, auto_builds_on_the_gpu_except_on_a_software_rasterizer) {
    using Build = VrcSpec::Build;
    for (const char* software : {"llvmpipe (LLVM 15.0.6, 256 bits)", "softpipe", "Mesa X11 swrast"}) {
        EXPECT_FALSE(gl::VrcRenderer::buildsOnGpu(Build::Auto, software)) << software;
        EXPECT_TRUE(gl::VrcRenderer::buildsOnGpu(Build::Gpu, software)) << software;
    }
    // AMD's Mesa driver names LLVM too; it is hardware.
    for (const char* hardware :
         {"NVIDIA GeForce RTX 3080/PCIe/SSE2", "AMD Radeon RX 6800 (navi21, LLVM 15.0.6, DRM 3.49)"}) {
        EXPECT_TRUE(gl::VrcRenderer::buildsOnGpu(Build::Auto, hardware)) << hardware;
        EXPECT_FALSE(gl::VrcRenderer::buildsOnGpu(Build::Cpu, hardware)) << hardware;
    }
    EXPECT_FALSE(gl::VrcRenderer::buildsOnGpu(Build::Auto, "")) << "no GL_RENDERER: the CPU build";
}

TEST_F(GlTest, vrc_auto_build_is_the_one_for_this_renderer_and_run_json_names_it) {
    const Scene scene = vrcScene(32, 24, 16, Transparency::KBuffer);
    ASSERT_EQ(scene.render.vrc.build, VrcSpec::Build::Auto);
    const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const StyledLines lines = randomLineScene(3, RandomSceneOptions{});
    std::unique_ptr<Technique> t = gl::createTechnique(scene, lines);
    EXPECT_EQ(t->describe()["build"], isSoftwareRasterizer(renderer) ? "cpu" : "gpu") << renderer;
}

}  // namespace
}  // namespace tc::test
