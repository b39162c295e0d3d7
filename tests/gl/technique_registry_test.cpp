// The technique registry (core/technique_registry.h) with every technique of the binary: each
// registered technique renders a small scene of every data kind it takes, its declared per-pixel
// bytes bound what it allocates, combinations it does not take are exit-2 errors naming the key,
// "auto" is the documented rule over the descriptors, and a particle series uploads and
// re-voxelizes a data frame only when the animation reaches it.
#include "core/technique_registry.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/animation.h"
#include "core/error.h"
#include "core/particle_generators.h"
#include "core/stage_sink.h"
#include "gl/gpu_timer.h"
#include "gl/objects.h"
#include "gl/techniques.h"
#include "gl_fixture.h"
#include "rt/techniques.h"
#include "test_scenes.h"

namespace tc {
namespace {

using test::GlTest;

const TechniqueRegistry& registry() {
    static const TechniqueRegistry r = [] {
        TechniqueRegistry out;
        gl::registerTechniques(out);
        rt::registerTechniques(out);
        return out;
    }();
    return r;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

Scene sceneFor(const TechniqueDescriptor& d, Transparency t, int w, int h) {
    Scene s;
    s.file = "scene.json";
    s.render.technique = RenderTechnique(d.name);
    s.render.transparency = t;
    s.style.opacity.constant = t == Transparency::Opaque ? 1.0f : 0.5f;
    s.image.width = w;
    s.image.height = h;
    return s;
}

// The inputs of one data kind: random tubes, or a droplet cloud of two data frames.
struct TestData {
    StyledLines lines = test::randomLineScene(7, options());
    ParticleData particles;
    static test::RandomSceneOptions options() {
        test::RandomSceneOptions o;
        o.polylines = 40;
        o.radiusMin = 0.04f;
        o.radiusRatio = 2.0f;
        return o;
    }
    TestData() {
        particles.frames.push_back(generateDroplets(300, 1));
        particles.frames.push_back(generateDroplets(200, 2));
    }
    TechniqueData of(DataKind kind) const {
        TechniqueData d;
        d.kind = kind;
        d.lines = &lines;
        d.particles = &particles;
        return d;
    }
    Bounds bounds(DataKind kind) const { return kind == DataKind::Lines ? lines.bounds : particles.bounds(); }
};

struct Rendered {
    FrameImages images;
    std::uint64_t allocated = 0;  // storage bytes allocated while creating and rendering
};

Rendered renderOnce(const TechniqueDescriptor& d, const Scene& scene, const TestData& data, DataKind kind) {
    const std::uint64_t before = gl::allocatedStorageBytes();
    std::unique_ptr<Technique> t = d.create(scene, data.of(kind), {});
    CameraSpec spec;
    spec.fit = true;
    const Camera cam = fitCamera(spec, data.bounds(kind), float(scene.image.width) / float(scene.image.height));
    gl::StageTimer timer;
    Rendered r;
    t->prepareFrame(0, timer);
    t->render(FrameSetup{0, cam, scene.image.width, scene.image.height}, r.images, timer);
    timer.collect();
    r.allocated = gl::allocatedStorageBytes() - before;
    return r;
}

std::size_t coveredPixels(const FrameImages& f) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < f.pixelCount(); ++i) n += f.rgba[4 * i + 3] > 0.0f;
    return n;
}

TEST_F(GlTest, every_registered_technique_renders_every_data_kind_and_mode_it_takes) {
    const TestData data;
    ASSERT_GE(registry().all().size(), 4u);
    for (const TechniqueDescriptor& d : registry().all())
        for (DataKind kind : d.data)
            for (Transparency t : d.transparency) {
                SCOPED_TRACE(d.name + " " + dataKindName(kind) + " " + transparencyName(t));
                const Scene scene = sceneFor(d, t, 48, 40);
                ASSERT_FALSE(checkTechnique(d, scene, kind)) << checkTechnique(d, scene, kind)->message;
                const Rendered r = renderOnce(d, scene, data, kind);
                ASSERT_EQ(r.images.width, 48);
                ASSERT_EQ(r.images.height, 40);
                const std::size_t covered = coveredPixels(r.images);
                EXPECT_GT(covered, 48u * 40u / 50) << "the fitted data is drawn";
                EXPECT_LT(covered, 48u * 40u) << "background remains around the fitted data";
            }
}

TEST_F(GlTest, declared_bytes_per_pixel_bound_what_each_technique_allocates_per_pixel) {
    // Two renders whose targets differ by 3x the pixels: what grows with the target is per-pixel
    // storage, and it must not exceed what the descriptor declares (tiling plans with it).
    const TestData data;
    for (const TechniqueDescriptor& d : registry().all())
        for (DataKind kind : d.data)
            for (Transparency t : d.transparency) {
                SCOPED_TRACE(d.name + " " + dataKindName(kind) + " " + transparencyName(t));
                Scene small = sceneFor(d, t, 64, 48);
                Scene large = sceneFor(d, t, 128, 96);
                small.render.culling.enabled = large.render.culling.enabled = d.name == "rasterized";
                const double extraPixels = 128.0 * 96.0 - 64.0 * 48.0;
                const double measured = (double(renderOnce(d, large, data, kind).allocated) -
                                         double(renderOnce(d, small, data, kind).allocated)) /
                                        extraPixels;
                const PixelBuffers declared = d.pixelBuffersFor(small, kind);
                EXPECT_LE(measured, double(declared.bytes))
                    << "declared " << declared.bytes << " (" << declared.what << ")";
                if (d.backend == TechniqueBackend::Cpu) {
                    EXPECT_EQ(declared.bytes, 0u);
                }
            }
}

TEST_F(GlTest, per_pixel_bytes_follow_the_renderers_allocations) {
    const TechniqueDescriptor& rasterized = *registry().find("rasterized");
    Scene s;
    s.render.transparency = Transparency::KBuffer;
    s.render.kbufferK = 8;
    PixelBuffers b = rasterized.pixelBuffersFor(s, DataKind::Lines);
    EXPECT_EQ(b.bytes, 16u + 64u + 4u + 36u);  // colour, entries, header, AOV G-buffer
    EXPECT_EQ(b.what, "kbuffer with k=8");
    EXPECT_EQ(b.largestStorage, 64u);
    s.output.aovDepth = s.output.aovNormal = s.output.aovId = false;
    s.render.culling.enabled = true;
    EXPECT_EQ(rasterized.pixelBuffersFor(s, DataKind::Lines).bytes, 16u + 64u + 4u + 2u + 2u);  // + pyramid, marks
    s.render.transparency = Transparency::Opaque;
    EXPECT_EQ(rasterized.pixelBuffersFor(s, DataKind::Lines).bytes, 36u + 20u + 2u);
    s.render.technique = RenderTechnique::Raytraced;
    EXPECT_EQ(registry().find("raytraced")->pixelBuffersFor(s, DataKind::Lines).bytes, 0u);
    s.render.transparency = Transparency::OpacityOptimization;
    EXPECT_FALSE(rasterized.composes(s));
}

TEST(TechniqueRegistry, unknown_technique_names_list_the_registered_ones) {
    Scene s;
    s.file = "scene.json";
    s.render.technique = RenderTechnique("kbuffer");
    EXPECT_EQ(errorOf([&] { registry().validate(s, DataKind::Lines); }),
              "scene.json: render.technique: expected one of \"auto\", \"rasterized\", \"spheres\", \"voxel_raycast\", "
              "\"raytraced\", got \"kbuffer\"");
}

TEST(TechniqueRegistry, combinations_a_technique_does_not_take_name_the_key) {
    Scene s;
    s.file = "scene.json";
    s.render.technique = RenderTechnique::Spheres;
    s.render.transparency = Transparency::KBuffer;
    EXPECT_EQ(
        errorOf([&] { registry().validate(s, DataKind::Particles); }),
        "scene.json: render.transparency: technique \"spheres\" takes \"opaque\" or \"object_order\", got \"kbuffer\"");
    s.render.technique = RenderTechnique::Rasterized;
    s.render.transparency = Transparency::Opaque;
    EXPECT_EQ(errorOf([&] { registry().validate(s, DataKind::Particles); }),
              "scene.json: render.technique: \"rasterized\" renders \"lines\", the dataset holds particles");
    s.render.ao.enabled = true;
    s.render.ao.method = AoSpec::Method::RayTraced;
    EXPECT_EQ(errorOf([&] { registry().validate(s, DataKind::Lines); }),
              "scene.json: render.ao.method: technique \"rasterized\" takes \"cone_traced\" ambient occlusion, got "
              "\"ray_traced\"");
    s.render.ao.method = AoSpec::Method::ConeTraced;
    s.render.transparency = Transparency::OpacityOptimization;
    EXPECT_EQ(errorOf([&] { registry().validate(s, DataKind::Lines); }),
              "scene.json: render.ao: not available with render.transparency \"opacity_optimization\"");
    s.render.technique = RenderTechnique::Raytraced;
    s.render.ao.enabled = false;
    EXPECT_EQ(
        errorOf([&] { registry().validateWithoutData(s); }),
        "scene.json: render.transparency: technique \"raytraced\" takes \"opaque\", \"object_order\", \"kbuffer\" "
        "or \"depth_peeling\", got \"opacity_optimization\"");
}

TEST(TechniqueRegistry, auto_prefers_the_cpu_on_a_software_rasterizer_and_says_why) {
    Scene s;
    s.render.technique = RenderTechnique::Auto;
    auto pick = [&](DataKind kind, const std::string& renderer) {
        return registry().resolveAuto(s, kind, renderer).descriptor->name;
    };
    const std::string llvmpipe = "llvmpipe (LLVM 15.0.6, 256 bits)", gpu = "NVIDIA GeForce RTX 4090/PCIe/SSE2";
    EXPECT_EQ(pick(DataKind::Lines, llvmpipe), "raytraced");
    EXPECT_EQ(pick(DataKind::Particles, llvmpipe), "raytraced");
    EXPECT_EQ(pick(DataKind::Lines, gpu), "rasterized");
    EXPECT_EQ(pick(DataKind::Particles, gpu), "spheres");
    EXPECT_EQ(registry().resolveAuto(s, DataKind::Lines, llvmpipe).why,
              "render.technique auto: raytraced (GL renderer \"llvmpipe (LLVM 15.0.6, 256 bits)\" is a software "
              "rasterizer)");
    // What only the GL path has sends auto back to it, and the log line says which setting.
    s.render.transparency = Transparency::OpacityOptimization;
    const TechniqueRegistry::AutoChoice choice = registry().resolveAuto(s, DataKind::Lines, llvmpipe);
    EXPECT_EQ(choice.descriptor->name, "rasterized");
    EXPECT_NE(choice.why.find("technique \"raytraced\" takes"), std::string::npos) << choice.why;
    EXPECT_NE(choice.why.find("(render.transparency)"), std::string::npos) << choice.why;
    // A transparency method the scene names is one the chosen technique implements: the ray
    // tracer renders kbuffer and object_order as exact compositing, so auto passes it over for them;
    // depth_peeling (exact) it renders as asked.
    s.render.transparency = Transparency::KBuffer;
    const TechniqueRegistry::AutoChoice kbuffer = registry().resolveAuto(s, DataKind::Lines, llvmpipe);
    EXPECT_EQ(kbuffer.descriptor->name, "rasterized");
    EXPECT_NE(kbuffer.why.find("raytraced renders render.transparency \"kbuffer\" as exact compositing"),
              std::string::npos)
        << kbuffer.why;
    s.render.transparency = Transparency::ObjectOrder;
    EXPECT_EQ(pick(DataKind::Lines, llvmpipe), "rasterized");
    EXPECT_EQ(pick(DataKind::Particles, llvmpipe), "spheres");
    s.render.transparency = Transparency::DepthPeeling;
    EXPECT_EQ(pick(DataKind::Lines, llvmpipe), "raytraced");
    // And ray-traced AO, which only the CPU path has, sends it to the CPU on a GPU.
    s.render.transparency = Transparency::Opaque;
    s.render.ao.enabled = true;
    s.render.ao.method = AoSpec::Method::RayTraced;
    EXPECT_EQ(pick(DataKind::Lines, gpu), "raytraced");
}

// Whether a frame's stages (CpuStageTimer::collect) include `stage`.
bool hasStage(const std::vector<StageTime>& stages, const std::string& stage) {
    return std::any_of(stages.begin(), stages.end(), [&](const StageTime& s) { return s.stage == stage; });
}

// A particle time series (docs/scene-spec.md "Time series"): the spheres technique uploads and
// re-voxelizes the ambient volume when the animation reaches another data frame, and only then
// (the paper voxelizes every frame); past the last data frame, and with dataset.frame pinned, it
// keeps the volume, and the frame is the same image as the last one with that data frame.
TEST_F(GlTest, a_particle_series_revoxelizes_when_the_data_frame_changes_and_only_then) {
    const TechniqueDescriptor* spheres = registry().find("spheres");
    ASSERT_NE(spheres, nullptr);
    ParticleData series;
    for (std::uint32_t seed : {1u, 2u, 3u}) series.frames.push_back(generateDroplets(250, seed));
    Scene scene = sceneFor(*spheres, Transparency::ObjectOrder, 40, 32);
    scene.render.ao.enabled = true;
    CameraSpec spec;
    spec.fit = true;
    const Camera cam = fitCamera(spec, series.bounds(), 40.0f / 32.0f);
    TechniqueData data;
    data.kind = DataKind::Particles;
    data.particles = &series;

    // Animation frames and the data frame each shows: 0 1 1 2 3(->2) 0.
    const std::vector<int> frames{0, 1, 1, 2, 3, 0};
    const std::vector<bool> newData{true, true, false, true, false, true};
    std::unique_ptr<Technique> t = spheres->create(scene, data, {});
    std::vector<FrameImages> images;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        SCOPED_TRACE("animation frame " + std::to_string(frames[i]) + " (step " + std::to_string(i) + ")");
        CpuStageTimer timer;
        t->prepareFrame(frames[i], timer);
        images.emplace_back();
        t->render(FrameSetup{frames[i], cam, 40, 32}, images.back(), timer);
        const std::vector<StageTime> stages = timer.collect();
        EXPECT_EQ(hasStage(stages, "voxelize"), bool(newData[i]));
        // The first data frame is uploaded when the technique is made, later ones when shown.
        EXPECT_EQ(hasStage(stages, "upload"), newData[i] && i > 0);
    }
    EXPECT_NE(images[0].rgba, images[1].rgba) << "another data frame, another image";
    EXPECT_EQ(images[1].rgba, images[2].rgba);
    EXPECT_EQ(images[3].rgba, images[4].rgba) << "past the last data frame: the last one again";
    EXPECT_EQ(images[0].rgba, images[5].rgba) << "back to data frame 0: voxelized again, same image";

    scene.dataset.frame = 1;  // pinned: one upload and one voxelization, whatever the frame
    std::unique_ptr<Technique> pinned = spheres->create(scene, data, {});
    for (int frame : {0, 2, 1, 5}) {
        SCOPED_TRACE("pinned, animation frame " + std::to_string(frame));
        CpuStageTimer timer;
        pinned->prepareFrame(frame, timer);
        FrameImages image;
        pinned->render(FrameSetup{frame, cam, 40, 32}, image, timer);
        const std::vector<StageTime> stages = timer.collect();
        EXPECT_EQ(hasStage(stages, "voxelize"), frame == 0);
        EXPECT_FALSE(hasStage(stages, "upload"));
        EXPECT_EQ(image.rgba, images[1].rgba) << "data frame 1";
    }
}

}  // namespace
}  // namespace tc
