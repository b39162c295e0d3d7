#pragma once
// Colormaps: sRGB control points interpolated in a stated colour space, as ParaView's
// vtkColorTransferFunction does (RGB, Lab, Diverging, HSV, Step), so that a ParaView preset
// (io/paraview_preset.h) looks the same here as there. Built-ins are generated from their
// published tables / endpoints (builtinColormap()).
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

namespace tc {

// How colours between two control points are interpolated (ParaView's "ColorSpace").
enum class ColorSpace {
    Rgb,        // componentwise on the stored (sRGB-encoded) values, as ParaView does
    Lab,        // CIE L*a*b* (D65), through the sRGB transfer function
    Diverging,  // Moreland's Msh space (Moreland 2009), white inserted between distinct hues
    Hsv,        // hue the short way round the circle (VTK's HSVWrap)
    Step,       // piecewise constant: (t_i, t_i+1] takes the colour of point i+1 (VTK's Step)
};

// The ParaView name ("RGB", "Lab", "Diverging", "HSV", "Step").
const char* colorSpaceName(ColorSpace space);

struct Colormap {
    std::string name;
    ColorSpace space = ColorSpace::Rgb;
    std::vector<float> t;               // ascending (equal neighbours make a jump), front 0, back 1
    std::vector<glm::vec3> srgb;        // one per t, components in [0,1]
    std::optional<glm::vec3> nanColor;  // sRGB colour for NaN values; unset: the style's default
    std::vector<glm::vec2> opacity;     // optional (t, alpha) transfer function (preset "Points")

    // sRGB colour at x, clamped to [0,1]; NaN gives nanColor (or mid grey).
    glm::vec3 sampleSrgb(float x) const;
};

// Throws InputError for unknown names; the list is in builtinColormapNames(). Built-ins:
// viridis, magma, inferno, plasma (matplotlib's 256-entry tables), turbo (Google's 256-entry
// table), cool_warm (Moreland's diverging map from its two published endpoints, interpolated in
// the Diverging space) and grayscale (black to white in RGB).
const Colormap& builtinColormap(const std::string& name);
std::vector<std::string> builtinColormapNames();
bool isBuiltinColormap(const std::string& name);

// Checks the invariants above; throws InputError "<source>: <what>" when violated.
void validateColormap(const Colormap& map, const std::string& source);

// Colour space conversions with the constants VTK's vtkMath uses (sRGB primaries, D65 white
// X=0.9505 Y=1 Z=1.089), so interpolated colours match ParaView's to float precision.
glm::vec3 srgbToLab(const glm::vec3& srgb);
glm::vec3 labToSrgb(const glm::vec3& lab);  // out-of-gamut colours are scaled/clamped as VTK does
glm::vec3 srgbToHsv(const glm::vec3& srgb);
glm::vec3 hsvToSrgb(const glm::vec3& hsv);

// Interpolates between two sRGB colours at s in [0,1] in the given space.
glm::vec3 interpolateSrgb(ColorSpace space, const glm::vec3& a, const glm::vec3& b, float s);

}  // namespace tc
