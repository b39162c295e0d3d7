#pragma once
// Draws a frame's overlay (core/overlay.h: colour legend, text labels, orientation triad) into its
// colour, after the background: text through OpenImageIO's ImageBufAlgo::render_text (FreeType),
// with the TrueType font overlay.font names.
#include <string>

#include "core/camera.h"
#include "core/colormap.h"
#include "core/frame_images.h"
#include "core/overlay.h"
#include "core/styling.h"

namespace tc {

// What one frame's overlay shows.
struct OverlayContent {
    const OverlaySpec* spec = nullptr;
    glm::vec4 background{0.0f};  // image.background (sRGB, straight alpha): picks the automatic text colour
    // The colour legend: a bar of `colormap` over `range` titled `title`; no bar without a colormap.
    const Colormap* colormap = nullptr;
    ValueRange range;
    std::string title;
    bool directionColors = false;  // style.color "direction": the direction key instead of a bar
    LabelValues labels;            // the text labels' placeholders
    Camera camera;                 // the triad's view
};

// The sRGB text colour that reads against an sRGB background with straight alpha: black on a light
// background, white on a dark or transparent one.
glm::vec3 automaticTextColor(const glm::vec4& background);

// Draws over frame.rgba (linear, premultiplied, composited over the background already): every
// overlay element of content.spec. Throws InputError "FONT: cannot render text: <reason>" when the
// font cannot be loaded.
void drawOverlay(FrameImages& frame, const OverlayContent& content);

// Throws InputError "<scene>: overlay.font: PATH: no such file (...)" when the font file is
// missing, so a run fails before its first frame.
void requireOverlayFont(const std::string& font, const std::string& sceneFile);

}  // namespace tc
