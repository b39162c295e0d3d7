#pragma once
// Styling: attributes -> per-vertex radius and linear straight RGBA, plus the segment index
// buffer the renderers draw from.
//
// - Each mapped attribute is normalised to t in [0,1] over its range: explicit [lo, hi], "auto"
//   (finite min/max) or percentiles of the finite values; values outside are clamped.
// - Radius: linear from radius_range[0] at t = 0 to radius_range[1] at t = 1.
// - Colour: the colormap (built-in, or style.color.preset loaded by io/paraview_preset.h) in its
//   own colour space, then linearised. Lab, Diverging and HSV maps are tabulated at t = k / 4096
//   first (a jump between equal control points is smeared over 1/4096). NaN values take style.color.nan_color, else the
//   preset's NanColor, else sRGB grey 0.5.
// - Opacity: the piecewise linear transfer function style.opacity.points (or the preset's).
// - NaN values get the low end for radius and opacity (t = 0).
// - Attributes the dataset lacks but core/derived_attributes.h can compute (curvature, ...) are
//   computed here, once per call.
#include <optional>
#include <string>

#include "core/line_set.h"
#include "core/scene.h"
#include "core/styled_lines.h"

namespace tc {

// Throws InputError naming `sceneFile` and the style key when an attribute is missing or
// cannot be derived.
StyledLines styleLines(const LineSet& lines, const StyleSpec& style, const std::string& sceneFile);

// The attribute values a mapping takes to t = 0 and t = 1 (lo == hi: every value to t = 0).
struct ValueRange {
    float lo = 0.0f, hi = 0.0f;
};

// The range styleLines maps style.color's attribute over (the colormap's ends: what a colour
// legend labels); nullopt when the colour is a constant or direction-encoded. Throws as styleLines
// for a missing attribute.
std::optional<ValueRange> colorMappingRange(const LineSet& lines, const StyleSpec& style, const std::string& sceneFile);

// Whether any vertex has an opacity below 1 (render.transparency "auto").
bool anyTranslucent(const StyledLines& lines);

// The piecewise linear transfer function of style.opacity at normalised t: held constant
// outside the points, the lower value exactly at a step, the first value for NaN; 1 without points.
float evaluateTransferFunction(const std::vector<glm::vec2>& points, float t);

// The value at percentile p in [0, 100] of the finite values (linear between order statistics,
// numpy's default); NaN when there is none.
float percentile(const std::vector<float>& values, float p);

// The colormap style.color names: the loaded preset, else the built-in. Throws InputError for a
// preset path that was never loaded (io/paraview_preset.h loadStylePresets).
const Colormap& styleColormap(const ColorSpec& color, const std::string& sceneFile);

}  // namespace tc
