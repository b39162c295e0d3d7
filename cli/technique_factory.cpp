#include "cli/technique_factory.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "gl/gpu_timer.h"
#include "rt/raytraced_particles.h"
#include "rt/raytraced_renderer.h"

namespace tc::cli {
namespace {

// rt/ reports CPU stages through rt::StageSink; the frame loop collects gl::StageTimer rows. Its
// GPU column then only measures the (idle) GL queue between the two timestamps.
class StageTimerSink final : public rt::StageSink {
public:
    explicit StageTimerSink(gl::StageTimer& timer) : m_timer(timer) {}
    void begin(std::string stage) override { m_timer.begin(std::move(stage)); }
    void end() override { m_timer.end(); }
    void setItems(std::uint64_t items) override { m_timer.setItems(items); }

private:
    gl::StageTimer& m_timer;
};

// Renderer: rt::RaytracedRenderer (tubes) or rt::RaytracedParticles.
template <class Renderer>
class RaytracedTechnique final : public gl::Technique {
public:
    explicit RaytracedTechnique(std::unique_ptr<Renderer> r) : m_renderer(std::move(r)) {}
    void render(const gl::FrameSetup& setup, FrameImages& out, gl::StageTimer& timer) override {
        StageTimerSink sink(timer);
        m_renderer->render(setup.camera, setup.width, setup.height, out, sink, setup.window);
    }
    nlohmann::json describe() const override { return m_renderer->describe(); }

private:
    std::unique_ptr<Renderer> m_renderer;
};

}  // namespace

RenderTechnique resolveTechnique(RenderTechnique requested, const std::string& glRenderer, std::string& why) {
    if (requested != RenderTechnique::Auto) return requested;
    std::string lower = glRenderer;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    for (const char* software : {"llvmpipe", "softpipe", "swrast"})
        if (lower.find(software) != std::string::npos) {
            why = std::string("render.technique auto: raytraced (GL renderer \"") + glRenderer +
                  "\" is a software rasterizer)";
            return RenderTechnique::Raytraced;
        }
    why = "render.technique auto: rasterized (GL renderer \"" + glRenderer + "\")";
    return RenderTechnique::Rasterized;
}

std::unique_ptr<gl::Technique> makeTechnique(const Scene& scene, const StyledLines& lines) {
    switch (scene.render.technique) {
    case RenderTechnique::Raytraced:
        return std::make_unique<RaytracedTechnique<rt::RaytracedRenderer>>(rt::RaytracedRenderer::create(scene, lines));
    case RenderTechnique::Spheres:  // a line dataset as spheres, one per vertex (gl::createTechnique)
    case RenderTechnique::Rasterized:
    case RenderTechnique::VoxelRaycast:  // gl::createTechnique; scene.cpp rejects ray_traced AO for it
        if (scene.render.ao.enabled && scene.render.ao.method == AoSpec::Method::RayTraced)
            throw InputError(scene.file + ": render.ao.method: \"ray_traced\" needs render.technique \"raytraced\" "
                                          "(or \"auto\" on a software renderer); use \"cone_traced\"");
        return gl::createTechnique(scene, lines);
    case RenderTechnique::Auto: break;
    }
    throw Error(ExitCode::Internal, "makeTechnique: render.technique auto must be resolved first");
}

std::unique_ptr<gl::Technique> makeRaytracedParticles(const Scene& scene, const StyledParticles& particles,
                                                      rt::RaytracedParticles*& renderer) {
    auto r = rt::RaytracedParticles::create(scene, particles);
    renderer = r.get();
    return std::make_unique<RaytracedTechnique<rt::RaytracedParticles>>(std::move(r));
}

}  // namespace tc::cli
