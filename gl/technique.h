#pragma once
// The interface between the frame loop (cli/render.cpp) and a render technique. A technique
// owns its passes and GPU resources; it never writes files.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/tiling.h"

namespace tc::gl {

class StageTimer;

struct FrameSetup {
    FrameSetup() = default;
    FrameSetup(int frame_, const Camera& camera_, int width_, int height_, const ImageWindow& window_ = {})
        : frame(frame_), camera(camera_), width(width_), height(height_), window(window_) {}

    int frame = 0;
    Camera camera;
    int width = 0, height = 0;  // the render target: the whole image, or one tile of it
    // Which part of the full image the target is and where its samples lie (tiles, image.samples;
    // gl/tiled_technique.h). Techniques pass it to the shaders with setViewWindowUniforms.
    ImageWindow window;
};

class Technique {
public:
    virtual ~Technique() = default;
    // Renders one frame into `out` (allocated by the technique to width x height), timing its
    // stages with `timer`.
    virtual void render(const FrameSetup& setup, FrameImages& out, StageTimer& timer) = 0;
    // What the technique chose (draw path, synchronisation, ...) for run.json.
    virtual nlohmann::json describe() const = 0;
};

// Prepares the technique the scene asks for (uploads, per-dataset work). The GL context must
// be current. Throws InputError for combinations that do not exist.
std::unique_ptr<Technique> createTechnique(const Scene& scene, const StyledLines& lines);

}  // namespace tc::gl
