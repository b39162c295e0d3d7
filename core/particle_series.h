#pragma once
// A particle time series behind a technique: the data frame each animation frame shows
// (min(frame, last), or dataset.frame pinned; docs/scene-spec.md "Time series"), styled when the
// animation reaches it and handed to the renderer, which re-uploads, re-voxelizes and re-sorts
// (the per-frame work of Staib et al. 2015's dynamic timings). Techniques for particles wrap their
// renderer in ParticleSeriesTechnique; the frame loop only calls Technique::prepareFrame.
#include <functional>
#include <memory>

#include "core/particle_set.h"
#include "core/scene.h"
#include "core/styled_particles.h"
#include "core/technique.h"

namespace tc {

// Bounds of the spheres over all data frames without styling them all: the positions' union grown
// by the largest radius the style or the data can give (for the camera fit and depth range).
Bounds particleSeriesBounds(const Scene& scene, const ParticleData& data);
// The largest radius the style or the data can give a sphere of any data frame (what
// particleSeriesBounds grows the positions by).
float particleSeriesMaxRadius(const Scene& scene, const ParticleData& data);

// Whether any particle of any data frame can get an opacity below 1 (render.transparency "auto"),
// from the style and the data's colours without styling every frame: a constant below 1, an
// opacity mapping whose transfer function goes below 1, or data colours with alpha below 1.
bool anyTranslucent(const StyleSpec& style, const ParticleData& data);

class ParticleSeriesTechnique final : public Technique {
public:
    // Replaces the renderer's particles; reports its own stages (e.g. "upload") to the sink.
    using Upload = std::function<void(const StyledParticles&, StageSink&)>;
    // Makes the renderer for the first shown data frame's styled particles.
    using Make = std::function<std::unique_ptr<Technique>(const StyledParticles&, Upload&)>;

    // Styles the data frame `firstFrame` shows and makes the renderer from it; `make` sets the
    // upload function for later data frames. Throws InputError for style attributes the data
    // lacks (naming the scene file and key).
    ParticleSeriesTechnique(const Scene& scene, const ParticleData& data, int firstFrame, const Make& make);

    // Uploads the data frame `frame` shows if it is not the one the renderer has.
    void prepareFrame(int frame, StageSink& sink) override;
    void render(const FrameSetup& setup, FrameImages& out, StageSink& sink) override {
        m_renderer->render(setup, out, sink);
    }
    nlohmann::json describe() const override { return m_renderer->describe(); }

    // The renderer (for tests that inspect it).
    Technique& renderer() { return *m_renderer; }

private:
    StyleSpec m_style;
    std::string m_sceneFile;
    int m_pinned = -1;
    const ParticleData& m_data;
    std::size_t m_current = 0;
    Upload m_upload;
    std::unique_ptr<Technique> m_renderer;
};

}  // namespace tc
