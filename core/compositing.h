#pragma once
#include <glm/glm.hpp>

#include "core/frame_images.h"

namespace tc {

// Composites a background (sRGB colour, straight alpha, as in image.background) under the
// premultiplied linear image: out = src + (1 - src.a) * bg. The last step of every frame.
void compositeUnder(FrameImages& images, const glm::vec4& backgroundSrgb);

}  // namespace tc
