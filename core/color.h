#pragma once
// sRGB transfer functions (IEC 61966-2-1). Colours in scene files and colormaps are sRGB;
// rendering and blending happen in linear space.
#include <cmath>
#include <glm/glm.hpp>

namespace tc {

inline float srgbToLinear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
inline float linearToSrgb(float c) {
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
inline glm::vec3 srgbToLinear(const glm::vec3& c) {
    return {srgbToLinear(c.x), srgbToLinear(c.y), srgbToLinear(c.z)};
}
inline glm::vec3 linearToSrgb(const glm::vec3& c) {
    return {linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z)};
}

}  // namespace tc
