#pragma once
// The overlay of each frame of `tubecast render` (docs/scene-spec.md "overlay"): what the legend,
// labels and triad show, from the scene and the data, handed to the frame loop as a function that
// draws into a frame's colour (io/frame_overlay.h).
#include <functional>
#include <string>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/scene.h"

namespace tc {
struct DatasetLoad;
}

namespace tc::cli {

// Draws the overlay of animation frame `frame` seen by `camera`. Safe to call from the frame
// writer's thread (it reads the scene and the data only).
using FrameOverlay = std::function<void(FrameImages& frame, int frameNumber, const Camera& camera)>;

// Null when the scene has no overlay. `scene` (with render.technique resolved) and `data` must
// outlive the function. The legend's range: the style.color mapping's, over the whole line set,
// or over each frame's particles (an automatic range follows the data frame). {time}: the data
// frame's time where the data has one, else frame / fps. `note` hears why a requested legend
// is not drawn (a constant colour).
FrameOverlay makeFrameOverlay(const Scene& scene, const DatasetLoad& data,
                              const std::function<void(const std::string&)>& note);

}  // namespace tc::cli
