#pragma once
// The interface between the frame loop (cli/frame_loop.h) and a render technique, GL or CPU. A
// technique owns its passes and its GPU or CPU resources and never writes files; it is created
// through its descriptor in the technique registry (core/technique_registry.h).
#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/stage_sink.h"
#include "core/tiling.h"

namespace tc {

struct FrameSetup {
    FrameSetup() = default;
    FrameSetup(int frame_, const Camera& camera_, int width_, int height_, const ImageWindow& window_ = {})
        : frame(frame_), camera(camera_), width(width_), height(height_), window(window_) {}

    int frame = 0;
    Camera camera;
    int width = 0, height = 0;  // the render target: the whole image, or one tile of it
    // Which part of the full image the target is and where its samples lie (tiles, image.samples;
    // core/tiling.h). GL techniques pass it to the shaders with gl::setViewWindowUniforms.
    ImageWindow window;
};

class Technique {
public:
    virtual ~Technique() = default;

    // The per-frame data hook, called once per animation frame before render() (and before the
    // tiles and samples of that frame): a particle time series uploads the data frame the
    // animation frame shows (core/particle_series.h). Stages go to `sink` like render()'s.
    virtual void prepareFrame(int /*frame*/, StageSink& /*sink*/) {}

    // Renders one frame into `out` (allocated by the technique to setup.width x setup.height),
    // reporting its stages to `sink`.
    virtual void render(const FrameSetup& setup, FrameImages& out, StageSink& sink) = 0;

    // What the technique chose (draw path, synchronisation, ...) for run.json.
    virtual nlohmann::json describe() const = 0;
};

}  // namespace tc
