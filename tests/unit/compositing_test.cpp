// Compositing (core/compositing.h): the background goes under the premultiplied image.
#include "core/compositing.h"

#include <gtest/gtest.h>

#include "core/color.h"

namespace tc {
namespace {

FrameImages onePixel(float r, float g, float b, float a) {
    FrameImages images;
    images.allocate(1, 1);
    images.rgba = {r, g, b, a};
    return images;
}

TEST(Compositing, OpaqueBackgroundUnderAHalfTransparentPixelIsTheAnalyticOver) {
    // Premultiplied linear (0.4, 0.2, 0, 0.5) over sRGB (1, 0.5, 0) opaque:
    // out = src + (1 - 0.5) * linear(bg), alpha 1.
    FrameImages images = onePixel(0.4f, 0.2f, 0.0f, 0.5f);
    compositeUnder(images, {1.0f, 0.5f, 0.0f, 1.0f});
    EXPECT_NEAR(images.rgba[0], 0.4f + 0.5f * 1.0f, 1e-6f);
    EXPECT_NEAR(images.rgba[1], 0.2f + 0.5f * 0.214041f, 1e-6f);
    EXPECT_NEAR(images.rgba[2], 0.0f, 1e-6f);
    EXPECT_NEAR(images.rgba[3], 1.0f, 1e-6f);
}

TEST(Compositing, HalfTransparentBackgroundIsPremultipliedBeforeCompositing) {
    FrameImages images = onePixel(0.0f, 0.0f, 0.0f, 0.0f);
    compositeUnder(images, {1.0f, 1.0f, 1.0f, 0.5f});
    EXPECT_NEAR(images.rgba[0], 0.5f, 1e-6f);
    EXPECT_NEAR(images.rgba[3], 0.5f, 1e-6f);
}

TEST(Compositing, OpaquePixelsAreNotChangedByTheBackground) {
    FrameImages images = onePixel(0.1f, 0.2f, 0.3f, 1.0f);
    compositeUnder(images, {1.0f, 1.0f, 1.0f, 1.0f});
    EXPECT_EQ(images.rgba, (std::vector<float>{0.1f, 0.2f, 0.3f, 1.0f}));
}

TEST(Compositing, TransparentBackgroundLeavesTheImageUnchanged) {
    FrameImages images;
    images.allocate(3, 2);
    for (std::size_t i = 0; i < images.rgba.size(); ++i) images.rgba[i] = 0.05f * float(i % 4);
    const std::vector<float> before = images.rgba;
    compositeUnder(images, {1.0f, 0.2f, 0.3f, 0.0f});
    EXPECT_EQ(images.rgba, before);
}

TEST(Compositing, OnlyColourIsTouched) {
    FrameImages images;
    images.allocate(2, 2);
    compositeUnder(images, {0.0f, 0.0f, 1.0f, 1.0f});
    for (std::size_t i = 0; i < images.pixelCount(); ++i) {
        EXPECT_FLOAT_EQ(images.rgba[4 * i + 2], 1.0f);
        EXPECT_FLOAT_EQ(images.rgba[4 * i + 3], 1.0f);
        EXPECT_EQ(images.id[i], kBackgroundId);
        EXPECT_TRUE(std::isinf(images.depth[i]));
    }
}

}  // namespace
}  // namespace tc
