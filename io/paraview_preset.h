#pragma once
// ParaView colour map presets (the JSON of ParaView's "Choose Preset" > Import / Export).
//
// A preset file holds one preset object or an array of them (the first is used):
//   {"Name": "...", "ColorSpace": "Diverging", "NanColor": [r, g, b],
//    "RGBPoints": [x0, r0, g0, b0, x1, r1, g1, b1, ...],
//    "Points": [x0, a0, midpoint0, sharpness0, ...]}            (opacity, optional)
// - RGBPoints positions are data values; they are rescaled to t in [0,1] (what ParaView does
//   when it applies a preset to a data range). Points are rescaled over their own span.
// - ColorSpace: "RGB", "Lab", "Diverging", "HSV", "Step"; "Lab/CIEDE2000" is read as "Lab"
//   (ParaView's CIEDE2000 path differs only in how it spaces the same Lab ramp). Missing: RGB.
// - Opacity segments with midpoint != 0.5 or sharpness != 0 (vtkPiecewiseFunction's Hermite
//   shaping) are resampled into 16 linear pieces, since style transfer functions are piecewise
//   linear.
// - Other keys (Creator, License, DefaultMap, Annotations, ...) are ignored; categorical
//   "IndexedColors" presets are rejected.
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "core/colormap.h"
#include "core/scene.h"

namespace tc {

// Reads a preset file. Throws InputError "PATH: ..." (with line:column for JSON syntax errors
// and the key for content errors, e.g. "PATH: RGBPoints: expected 4 numbers per point").
Colormap readParaViewPreset(const std::string& path);

// Converts one parsed preset object; `source` prefixes error messages.
Colormap colormapFromParaViewPreset(const nlohmann::json& preset, const std::string& source);

// The preset object for `map` (t as positions, so reading it back gives the same Colormap).
nlohmann::json paraViewPresetFromColormap(const Colormap& map);

// Writes [preset] as ParaView exports it, through an AtomicFile. Throws OutputError.
void writeParaViewPreset(const Colormap& map, const std::string& path);

// JSON text with the commas before a closing ']' or '}' removed (outside strings). ParaView's
// own exported preset files have them, nlohmann::json 3.11 (Debian 12) rejects them and has no
// option to allow them (ignore_trailing_commas arrived in 3.12). Byte offsets change only by the
// removed commas, which are replaced by spaces so error positions stay right.
std::string stripTrailingCommas(std::string_view json);

// Loads style.color.colormap when it names a preset file into style.color.preset. Throws
// InputError "<sceneFile>: style.color.colormap: <preset error>".
void loadStylePresets(StyleSpec& style, const std::string& sceneFile);

}  // namespace tc
