#include "core/compositing.h"

#include "core/color.h"

namespace tc {

void compositeUnder(FrameImages& images, const glm::vec4& backgroundSrgb) {
    const float a = backgroundSrgb.w;
    if (a <= 0.0f) return;
    const glm::vec3 bg = srgbToLinear(glm::vec3(backgroundSrgb)) * a;
    for (std::size_t i = 0; i < images.pixelCount(); ++i) {
        float* p = &images.rgba[4 * i];
        float t = 1.0f - p[3];
        p[0] += t * bg.x;
        p[1] += t * bg.y;
        p[2] += t * bg.z;
        p[3] += t * a;
    }
}

}  // namespace tc
