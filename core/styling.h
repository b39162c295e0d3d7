#pragma once
// Styling: attributes -> per-vertex radius and linear straight RGBA, plus the segment index
// buffer the renderers draw from.
#include <string>

#include "core/line_set.h"
#include "core/scene.h"
#include "core/styled_lines.h"

namespace tc {

// Throws InputError naming `sceneFile` and the style key when an attribute is missing.
StyledLines styleLines(const LineSet& lines, const StyleSpec& style, const std::string& sceneFile);

// The piecewise linear transfer function of style.opacity at normalised t.
float evaluateTransferFunction(const std::vector<glm::vec2>& points, float t);

}  // namespace tc
