#pragma once
// Built-in colormaps as sRGB control points, interpolated in sRGB (M5 adds Lab / diverging
// interpolation and ParaView preset import).
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace tc {

struct Colormap {
    std::string name;
    std::vector<float> t;           // ascending, t.front() = 0, t.back() = 1
    std::vector<glm::vec3> srgb;

    glm::vec3 sampleSrgb(float x) const;  // x clamped to [0,1]
};

// Throws InputError for unknown names; the list is in builtinColormapNames().
const Colormap& builtinColormap(const std::string& name);
std::vector<std::string> builtinColormapNames();

}  // namespace tc
