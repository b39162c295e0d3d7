// render.vrc.encoding "paper" (core/vrc_packed.h, the packed pieces of Kanzler et al. 2019,
// Table I) in the ray caster against the 16-byte encoding. With one colour and one radius and
// q = 64 (the packed vertex lattice is the model's own from q = 33 on) the packed model loses
// nothing, so colour, depth, normal and polyline id must be bit-identical, opaque and transparent.
// Where the packed encoding cannot serve (neighbour tests compare line ids across voxels) the
// renderer falls back to the 16-byte one and says so in run.json.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/scene.h"
#include "core/technique.h"
#include "gl/gpu_timer.h"
#include "gl/vrc_renderer.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

// Random bent polylines (many crossing a voxel, several per voxel), one colour and one radius.
StyledLines uniformLines(float alpha, int polylines = 60) {
    RandomSceneOptions o;
    o.polylines = polylines;
    o.minSegments = 4;
    o.maxSegments = 12;
    o.stepMin = 0.1f;
    o.stepMax = 0.3f;
    StyledLines lines = randomLineScene(21, o);
    for (glm::vec4& p : lines.positionRadius) p.w = 0.03f;
    // Channels away from the RGBA8 rounding edges (x.5 / 255): the colour interpolated to a face
    // hit differs from the vertex colour by float rounding.
    for (glm::vec4& c : lines.color) c = glm::vec4(0.21f, 0.62f, 0.83f, alpha);
    lines.maxRadius = 0.03f;
    return lines;
}

Scene scene(bool transparent, int q, bool paper, bool neighbors) {
    Scene s;
    s.image.width = 120;
    s.image.height = 90;
    s.render.technique = RenderTechnique::VoxelRaycast;
    s.render.transparency = transparent ? Transparency::KBuffer : Transparency::Opaque;
    s.render.vrc.resolution = 20;
    s.render.vrc.quantization = q;
    s.render.vrc.neighbors = neighbors;
    s.render.vrc.opacityThreshold = 1.0f;
    s.render.vrc.build = VrcSpec::Build::Cpu;
    s.render.vrc.encoding = paper ? VrcSpec::Encoding::Paper : VrcSpec::Encoding::Compact16;
    s.output.aovId = true;
    return s;
}

FrameImages render(Technique& t, const Scene& s) {
    Camera cam;
    cam.eye = {0.9f, 0.6f, 2.6f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 45.0f;
    gl::StageTimer timer;
    FrameImages out;
    t.render(FrameSetup{0, cam, s.image.width, s.image.height}, out, timer);
    timer.collect();
    return out;
}

void expectSameImages(const FrameImages& a, const FrameImages& b) {
    std::size_t covered = 0;
    for (std::uint32_t id : a.id) covered += id != kBackgroundId;
    EXPECT_GT(covered, a.id.size() / 5);
    EXPECT_EQ(a.rgba, b.rgba);
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(a.normal.data(), b.normal.data(), a.normal.size() * sizeof(float)), 0);
}

TEST_F(GlTest, vrc_paper_encoding_renders_the_compact16_image_bit_for_bit_with_one_colour_and_radius) {
    for (bool transparent : {false, true}) {
        SCOPED_TRACE(transparent ? "transparent" : "opaque");
        const StyledLines lines = uniformLines(transparent ? 0.35f : 1.0f);
        const Scene compact = scene(transparent, 64, false, false), paper = scene(transparent, 64, true, false);
        const std::unique_ptr<gl::VrcRenderer> a = gl::VrcRenderer::create(compact, lines);
        const std::unique_ptr<gl::VrcRenderer> b = gl::VrcRenderer::create(paper, lines);
        const nlohmann::json da = a->describe(), db = b->describe();
        EXPECT_EQ(da["encoding"], "compact16");
        ASSERT_EQ(db["encoding"], "paper") << db["encoding_fallback"];
        EXPECT_GT(int(da["copies"]), 0);
        // q = 64 with copies and one radius: 2 x 15 + 8 + 5 + 6 = 49 bits.
        EXPECT_EQ(db["bytes_per_piece"], 7);
        EXPECT_EQ(db["paper_encoding"]["palette_colors"], 1);
        EXPECT_EQ(db["pieces"], da["pieces"]);
        EXPECT_EQ(std::size_t(db["header_bytes"]), std::size_t(da["header_bytes"]) / 8 * 5);
        EXPECT_EQ(std::size_t(db["model_bytes"]), std::size_t(db["header_bytes"]) + 7 * std::size_t(db["pieces"]));
        EXPECT_EQ(std::size_t(da["model_bytes"]), std::size_t(da["header_bytes"]) + 16 * std::size_t(da["pieces"]));
        expectSameImages(render(*a, compact), render(*b, paper));
    }
}

TEST_F(GlTest, vrc_paper_encoding_without_the_id_output_keeps_colour_and_depth) {
    // Without the id output the ray caster tells lines apart by their local ids alone: the
    // blending (each line once per voxel) must be the same.
    const StyledLines lines = uniformLines(0.35f);
    Scene compact = scene(true, 64, false, false), paper = scene(true, 64, true, false);
    paper.output.aovId = false;
    const std::unique_ptr<gl::VrcRenderer> a = gl::VrcRenderer::create(compact, lines);
    const std::unique_ptr<gl::VrcRenderer> b = gl::VrcRenderer::create(paper, lines);
    ASSERT_EQ(b->describe()["encoding"], "paper");
    EXPECT_EQ(b->describe()["paper_encoding"]["global_id_bytes"], 0);
    const FrameImages fa = render(*a, compact), fb = render(*b, paper);
    EXPECT_EQ(fa.rgba, fb.rgba);
    EXPECT_EQ(std::memcmp(fa.depth.data(), fb.depth.data(), fa.depth.size() * sizeof(float)), 0);
}

TEST_F(GlTest, vrc_paper_encoding_with_wide_local_ids_and_counts_renders_the_compact16_image) {
    // 400 polylines in a 3^3 grid: voxels with hundreds of polylines and more than 255 pieces,
    // so the local line id widens and the header count takes 2 bytes. Without the id output the
    // ray caster tells the lines of a voxel apart by the wide local ids alone.
    for (bool transparent : {false, true})
        for (bool ids : {true, false}) {
            SCOPED_TRACE(std::string(transparent ? "transparent" : "opaque") + (ids ? ", ids" : ", no ids"));
            const StyledLines lines = uniformLines(transparent ? 0.35f : 1.0f, 400);
            Scene compact = scene(transparent, 64, false, false), paper = scene(transparent, 64, true, false);
            compact.render.vrc.resolution = paper.render.vrc.resolution = 3;
            compact.output.aovId = paper.output.aovId = ids;
            const std::unique_ptr<gl::VrcRenderer> a = gl::VrcRenderer::create(compact, lines);
            const std::unique_ptr<gl::VrcRenderer> b = gl::VrcRenderer::create(paper, lines);
            const nlohmann::json db = b->describe();
            ASSERT_EQ(db["encoding"], "paper") << db["encoding_fallback"];
            EXPECT_GT(int(db["paper_encoding"]["local_line_bits"]), 5);
            EXPECT_EQ(db["paper_encoding"]["header_count_bytes"], 2);
            const FrameImages fa = render(*a, compact), fb = render(*b, paper);
            std::size_t covered = 0;
            for (float d : fa.depth) covered += std::isfinite(d);
            EXPECT_GT(covered, fa.depth.size() / 5);
            EXPECT_EQ(fa.rgba, fb.rgba);
            EXPECT_EQ(std::memcmp(fa.depth.data(), fb.depth.data(), fa.depth.size() * sizeof(float)), 0);
            if (ids) {
                EXPECT_EQ(fa.id, fb.id);
            }
        }
}

TEST_F(GlTest, vrc_paper_encoding_at_q32_stays_close_to_compact16) {
    // q = 32: 6 bytes per piece with copies; only the vertex ends move (12^3 lattice instead of
    // 16^3), so the images differ at line ends only.
    const StyledLines lines = uniformLines(1.0f);
    const Scene compact = scene(false, 32, false, false), paper = scene(false, 32, true, false);
    const std::unique_ptr<gl::VrcRenderer> a = gl::VrcRenderer::create(compact, lines);
    const std::unique_ptr<gl::VrcRenderer> b = gl::VrcRenderer::create(paper, lines);
    ASSERT_EQ(b->describe()["encoding"], "paper");
    EXPECT_EQ(b->describe()["bytes_per_piece"], 6);
    const FrameImages fa = render(*a, compact), fb = render(*b, paper);
    std::size_t differ = 0, covered = 0;
    for (std::size_t i = 0; i < fa.id.size(); ++i) {
        covered += fa.id[i] != kBackgroundId;
        differ += fa.id[i] != fb.id[i];
    }
    EXPECT_GT(differ, 0u);  // the vertex ends did move
    EXPECT_LT(differ, covered / 20);
}

TEST_F(GlTest, vrc_paper_encoding_with_neighbor_tests_falls_back_to_compact16) {
    const StyledLines lines = uniformLines(0.35f);
    const Scene compact = scene(true, 32, false, true), paper = scene(true, 32, true, true);
    const std::unique_ptr<gl::VrcRenderer> a = gl::VrcRenderer::create(compact, lines);
    const std::unique_ptr<gl::VrcRenderer> b = gl::VrcRenderer::create(paper, lines);
    const nlohmann::json d = b->describe();
    EXPECT_EQ(d["encoding"], "compact16");
    EXPECT_EQ(d["encoding_requested"], "paper");
    ASSERT_TRUE(d["encoding_fallback"].is_string());
    EXPECT_NE(std::string(d["encoding_fallback"]).find("render.vrc.neighbors"), std::string::npos);
    EXPECT_EQ(d["bytes_per_piece"], 16);
    EXPECT_TRUE(a->describe()["encoding_fallback"].is_null());
    expectSameImages(render(*a, compact), render(*b, paper));
}

}  // namespace
}  // namespace tc::test
