#pragma once
// 8-bit sRGB encoding of linear values by table: the output path converts every pixel of every
// frame (2M pixels x 3 channels at 1920x1080), and three powf per pixel cost more than zlib's
// fastest level (docs/performance.md, "Design notes"). The table is built from linearToSrgb
// itself (core/color.h), so the result is bit-identical to the formula it replaces.
#include <cstdint>

namespace tc {

// lround(255 * linearToSrgb(clamp(v, 0, 1))); NaN encodes as 0.
std::uint8_t linearToSrgb8(float v);

// The same, by evaluating the formula (the definition; for tests).
std::uint8_t linearToSrgb8Direct(float v);

}  // namespace tc
