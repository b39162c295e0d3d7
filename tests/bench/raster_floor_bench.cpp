// The rasterized line technique against its fragment floor: the same billboards (same billboard
// path and shape, same data, same view) drawn with a fragment shader that writes one constant
// colour (shaders/billboard_floor.frag), i.e. what rasterizing and shading the billboards' fragments
// costs before any ray-cone test, against the draw stages of the opaque path (stage "gbuffer":
// the visibility draw) and of the k-buffer (stages "kbuffer" + "resolve") for each k. Every case
// is made once, rendered once to warm up (llvmpipe compiles shader variants at the first draw),
// then the cases take turns, forward and backward (A B C .. C B A), so load on a shared machine
// hits them alike; a row is the median over the rounds. Each stage is timed between two
// glFinish() calls, as wall time and as the CPU time of the whole process (every llvmpipe thread:
// the work done, which other processes on a loaded machine do not inflate the way they stretch
// wall time). The floor draw's fragments (every pixel a billboard covers, i.e. the
// ray-cone tests a line pass runs) are counted too.
// Run by scripts/bench/raster_floor.sh.
//
//   tubecast_raster_floor_bench SCENE.json [--rounds 4] [--k 4,8,16] [--opacity 0.3] [--set key=value ...]
//                               [--shader-dir DIR]   (shader files there replace the built-in ones)
//
// The scene's own transparency and AOVs are replaced: opaque at its style's opacity 1, the
// k-buffer rows at --opacity, no AOVs (the transparent path would draw a G-buffer for them).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/animation.h"
#include "core/error.h"
#include "core/scene.h"
#include "core/styling.h"
#include "core/technique.h"
#include "gl/context.h"
#include "gl/gl_api.h"
#include "gl/line_geometry.h"
#include "gl/objects.h"
#include "gl/shader_library.h"
#include "gl/techniques.h"
#include "io/dataset.h"

namespace {

using namespace tc::bench;

double processCpuMs() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return 1e3 * (double(usage.ru_utime.tv_sec) + double(usage.ru_stime.tv_sec)) +
           1e-3 * (double(usage.ru_utime.tv_usec) + double(usage.ru_stime.tv_usec));
}

struct Stage {
    std::string name;
    double wallMs = 0, cpuMs = 0;  // cpuMs: all threads of the process
};

// Times each stage between glFinish() calls (the GL timestamps of gl::StageTimer do not see the
// vertex work llvmpipe does on the calling thread, and measure wall time only).
class FinishedStageTimer final : public tc::StageSink {
public:
    void begin(std::string stage) override {
        glFinish();
        m_open = {std::move(stage), 0, 0};
        m_wall0 = std::chrono::steady_clock::now();
        m_cpu0 = processCpuMs();
    }
    void end() override {
        glFinish();
        m_open.wallMs = msSince(m_wall0);
        m_open.cpuMs = processCpuMs() - m_cpu0;
        m_stages.push_back(m_open);
    }
    void setItems(std::uint64_t) override {}
    std::vector<Stage> take() { return std::move(m_stages); }

private:
    Stage m_open;
    Clock::time_point m_wall0;
    double m_cpu0 = 0;
    std::vector<Stage> m_stages;
};

// The constant-colour draw of every billboard into an RGBA32F target (the colour target's format of
// the transparent path), no depth test, no blending.
class FloorDraw {
public:
    FloorDraw(const tc::Scene& scene, const tc::StyledLines& lines)
        : m_geometry(tc::gl::LineGeometry::create(lines, scene.render.billboards, {}, scene.render.billboardShape)) {
        m_program = m_geometry.compileDrawProgram("billboard_floor.frag");
        m_color = tc::gl::makeTexture2D(GL_RGBA32F, scene.image.width, scene.image.height);
        m_framebuffer = tc::gl::makeFramebuffer({&m_color}, nullptr, "floor target");
        m_lighting = scene.lighting;
    }

    // The stages: "billboards" (the pre-pass, as the techniques have it) and "floor", the draw.
    std::vector<Stage> render(const tc::FrameSetup& setup) {
        FinishedStageTimer timer;
        m_geometry.setFrame(setup, m_lighting);
        m_geometry.computeBillboards(timer);
        timer.begin("floor");
        glBindFramebuffer(GL_FRAMEBUFFER, m_framebuffer.id());
        glViewport(0, 0, setup.width, setup.height);
        const float zero[4] = {0, 0, 0, 0};
        glClearNamedFramebufferfv(m_framebuffer.id(), GL_COLOR, 0, zero);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_BLEND);
        glDisable(GL_CULL_FACE);
        glUseProgram(m_program.id());
        glBeginQuery(GL_SAMPLES_PASSED, m_fragmentsQuery.id());
        m_geometry.draw(0, m_geometry.segmentCount());
        glEndQuery(GL_SAMPLES_PASSED);
        timer.end();
        glGetQueryObjectui64v(m_fragmentsQuery.id(), GL_QUERY_RESULT, &m_fragments);
        return timer.take();
    }

    // The fragments of the last draw: every pixel a billboard covers, once per billboard (no depth
    // test), i.e. the ray-cone tests a line pass runs.
    std::uint64_t fragments() const { return m_fragments; }

private:
    tc::gl::LineGeometry m_geometry;
    tc::gl::Program m_program;
    tc::gl::Texture m_color;
    tc::gl::Framebuffer m_framebuffer;
    tc::LightingSpec m_lighting;
    tc::gl::Query m_fragmentsQuery = tc::gl::Query::create(GL_SAMPLES_PASSED);
    GLuint64 m_fragments = 0;
};

struct Case {
    std::string name;
    std::vector<std::string> drawStages;  // what counts as the draw
    std::unique_ptr<tc::Technique> technique;
    std::unique_ptr<FloorDraw> floor;
    std::vector<double> drawCpu = {}, drawWall = {}, frameWall = {};
    std::vector<std::vector<Stage>> stages = {};  // every stage of each round
};

// Renders one frame of `c` and records its times.
void renderCase(Case& c, const tc::FrameSetup& setup) {
    std::vector<Stage> stages;
    if (c.floor) {
        stages = c.floor->render(setup);
    } else {
        FinishedStageTimer timer;
        tc::FrameImages images;
        c.technique->render(setup, images, timer);
        stages = timer.take();
    }
    double cpu = 0, wall = 0, frame = 0;
    for (const Stage& s : stages) {
        frame += s.wallMs;
        for (const std::string& d : c.drawStages)
            if (s.name == d) {
                cpu += s.cpuMs;
                wall += s.wallMs;
            }
    }
    c.drawCpu.push_back(cpu);
    c.drawWall.push_back(wall);
    c.frameWall.push_back(frame);
    c.stages.push_back(std::move(stages));
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE.json [--rounds R] [--k 4,8,16] [--opacity A] [--set key=value ...]\n",
                     argv[0]);
        return 2;
    }
    const std::string path = argv[1];
    int rounds = 4;
    std::vector<std::size_t> ks{4, 8, 16};
    std::string opacity = "0.3";
    std::vector<std::string> overrides;
    for (int i = 2; i < argc; i += 2) {
        const std::string flag = argv[i];
        if (i + 1 >= argc) {
            std::fprintf(stderr, "error: %s needs a value\n", argv[i]);
            return 2;
        }
        if (flag == "--rounds")
            rounds = std::atoi(argv[i + 1]);
        else if (flag == "--k")
            ks = parseList(argv[i + 1]);
        else if (flag == "--opacity")
            opacity = argv[i + 1];
        else if (flag == "--set")
            overrides.push_back(argv[i + 1]);
        else if (flag == "--shader-dir")
            tc::gl::ShaderLibrary::instance().setOverrideDir(argv[i + 1]);
        else {
            std::fprintf(stderr, "error: unknown option %s\n", argv[i]);
            return 2;
        }
    }

    const tc::gl::Context context = tc::gl::Context::create(tc::gl::ContextConfig{});
    // One scene per case: the same file and overrides, then the case's transparency.
    auto sceneFor = [&](const std::vector<std::string>& extra) {
        std::vector<std::string> all = overrides;
        all.push_back("output.aovs=[]");
        all.insert(all.end(), extra.begin(), extra.end());
        return tc::loadScene(path, all);
    };
    const tc::Scene opaqueScene = sceneFor({"render.transparency=\"opaque\"", "style.opacity=1"});
    const tc::DatasetLoad data = tc::loadDataset(opaqueScene.dataset);
    const tc::StyledLines opaqueLines = tc::styleLines(data.lines, opaqueScene.style, opaqueScene.file);
    const tc::Camera camera =
        tc::cameraAtFrame(opaqueScene.animation,
                          tc::fitCamera(opaqueScene.camera, opaqueLines.bounds,
                                        float(opaqueScene.image.width) / float(opaqueScene.image.height)),
                          0);
    const tc::FrameSetup setup{0, camera, opaqueScene.image.width, opaqueScene.image.height};

    std::vector<Case> cases;
    cases.push_back(
        {"floor (constant colour)", {"floor"}, nullptr, std::make_unique<FloorDraw>(opaqueScene, opaqueLines)});
    cases.push_back({"opaque", {"gbuffer"}, tc::gl::createTechnique(opaqueScene, opaqueLines), nullptr});
    const tc::Scene transparentScene = sceneFor({"style.opacity=" + opacity});
    const tc::StyledLines transparentLines = tc::styleLines(data.lines, transparentScene.style, transparentScene.file);
    for (std::size_t k : ks) {
        const tc::Scene s = sceneFor(
            {"style.opacity=" + opacity, "render.transparency=\"kbuffer\"", "render.kbuffer.k=" + std::to_string(k)});
        cases.push_back({"k-buffer k=" + std::to_string(k),
                         {"kbuffer", "resolve"},
                         tc::gl::createTechnique(s, transparentLines),
                         nullptr});
    }
    for (Case& c : cases) {  // warm-up
        renderCase(c, setup);
        c = Case{std::move(c.name), std::move(c.drawStages), std::move(c.technique), std::move(c.floor)};
    }
    for (int r = 0; r < rounds; ++r)
        for (std::size_t i = 0; i < cases.size(); ++i) renderCase(cases[r % 2 == 0 ? i : cases.size() - 1 - i], setup);

    const double floorCpu = median(cases[0].drawCpu), floorWall = median(cases[0].drawWall);
    std::printf("| case | draw CPU ms | multiple (CPU) | draw wall ms | multiple (wall) | frame wall ms |\n");
    std::printf("|---|---:|---:|---:|---:|---:|\n");
    for (const Case& c : cases)
        std::printf("| %s | %.0f | %.2f | %.0f | %.2f | %.0f |\n", c.name.c_str(), median(c.drawCpu),
                    median(c.drawCpu) / floorCpu, median(c.drawWall), median(c.drawWall) / floorWall,
                    median(c.frameWall));
    std::printf("\nPer stage, median wall ms (CPU ms of all threads):\n\n");
    for (const Case& c : cases) {
        std::string line;
        for (std::size_t i = 0; i < c.stages.front().size(); ++i) {
            std::vector<double> wall, cpu;
            for (const std::vector<Stage>& round : c.stages) {
                wall.push_back(round[i].wallMs);
                cpu.push_back(round[i].cpuMs);
            }
            char buf[160];
            std::snprintf(buf, sizeof buf, "%s%s %.0f (%.0f)", line.empty() ? "" : ", ",
                          c.stages.front()[i].name.c_str(), median(wall), median(cpu));
            line += buf;
        }
        std::printf("- %s: %s\n", c.name.c_str(), line.c_str());
    }
    std::printf(
        "\n%s: %zu segments, %dx%d, %d rounds; draw: floor = the constant-colour draw, opaque = stage "
        "gbuffer, k-buffer = stages kbuffer + resolve; frame: every stage of the frame; the floor draw's "
        "fragments (billboard pixels): %llu\n",
        path.c_str(), opaqueLines.segmentCount(), setup.width, setup.height, rounds,
        static_cast<unsigned long long>(cases[0].floor->fragments()));
    return 0;
} catch (const tc::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
}
