// cli::IcetCompositor under N ranks against CPU composites of the same synthetic per-rank images,
// which every rank can regenerate for every other rank.
#include "cli/icet_compositor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>

#include "core/color.h"
#include "core/compositing.h"
#include "mpi/mpi_test_session.h"

namespace tc::test {
namespace {

using cli::CompositeMode;
using cli::IcetCompositor;
using cli::MpiSession;

constexpr int kW = 37;  // odd sizes: no power-of-two split of the image lines up by accident
constexpr int kH = 23;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kBackgroundAo = 0.75f;  // what every rank writes where it has no surface

enum Salt : std::uint64_t { kDepth = 1, kCover, kColor, kNormal, kId, kAo, kAlpha };

// The view depth of rank r at pixel i, or +inf. Depths span 2^-40 .. 2^40 (every binade of the
// key mapping is exercised); every 17th pixel has the same depth on every rank (a tie); pixels
// with i % 11 == 0 are background on every rank.
float depthOf(int r, std::size_t i) {
    if (i % 11 == 0) return kInf;
    if (i % 17 == 0) return 3.5f;
    if (unit(std::uint64_t(r), i, kCover) < 0.3f) return kInf;
    return std::exp2(-40.0f + 80.0f * unit(std::uint64_t(r), i, kDepth));
}

// An id with every bit pattern the fourth float of the "aov" pass must carry: signalling and quiet
// NaN patterns, infinities, denormals, -0, and random ones.
std::uint32_t idOf(int r, std::size_t i) {
    static const std::uint32_t special[] = {0x7F800001u, 0xFF800001u, 0x7FC00000u, 0xFFFFFFFEu,
                                            0x7F800000u, 0x80000000u, 0x00000001u, 0u};
    if (i % 5 == 0) return special[(i / 5 + std::size_t(r)) % 8];
    return std::uint32_t(hash3(std::uint64_t(r), i, kId));
}

// Rank r's opaque image: surfaces where depthOf is finite (alpha 1, random colour, a random
// normal, idOf, random ao), tubecast's background elsewhere.
FrameImages opaqueLayer(int r, bool ao) {
    FrameImages img;
    img.allocate(kW, kH);
    if (ao) img.ao.assign(img.pixelCount(), kBackgroundAo);
    for (std::size_t i = 0; i < img.pixelCount(); ++i) {
        float d = depthOf(r, i);
        if (!(d < kInf)) continue;
        img.depth[i] = d;
        for (int c = 0; c < 3; ++c) {
            img.rgba[4 * i + std::size_t(c)] = unit(std::uint64_t(r), i, kColor + 16 * std::uint64_t(c));
            img.normal[3 * i + std::size_t(c)] =
                2.0f * unit(std::uint64_t(r), i, kNormal + 16 * std::uint64_t(c)) - 1.0f;
        }
        img.rgba[4 * i + 3] = 1.0f;
        img.id[i] = idOf(r, i);
        if (ao) img.ao[i] = unit(std::uint64_t(r), i, kAo);
    }
    return img;
}

// Rank r's transparent layer: premultiplied colour with alpha in [0.05, 0.95] where the rank has a
// surface (its first surface's depth, normal and id as opaqueLayer), nothing elsewhere.
FrameImages transparentLayer(int r, bool ao) {
    FrameImages img = opaqueLayer(r, ao);
    for (std::size_t i = 0; i < img.pixelCount(); ++i) {
        if (!(img.depth[i] < kInf)) continue;
        float a = 0.05f + 0.9f * unit(std::uint64_t(r), i, kAlpha);
        for (int c = 0; c < 3; ++c) img.rgba[4 * i + std::size_t(c)] *= a;
        img.rgba[4 * i + 3] = a;
    }
    return img;
}

// A front-to-back order that is neither rank order nor its reverse (for N >= 3).
std::vector<int> viewOrder(int n) {
    std::vector<int> order(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) order[std::size_t(k)] = (2 * k + 1) % n;
    if (n % 2 == 0) {  // 2k+1 mod n is not a permutation for even n: odd ranks descending, then even
        order.clear();
        for (int r = n - 1; r >= 0; r -= 2) order.push_back(r);
        for (int r = 0; r < n; r += 2) order.push_back(r);
    }
    return order;
}

// The ranks whose depth at pixel i is the smallest (more than one on ties); empty on background.
std::vector<int> nearestRanks(const std::vector<FrameImages>& layers, std::size_t i) {
    float best = kInf;
    std::vector<int> ranks;
    for (int r = 0; r < int(layers.size()); ++r) {
        float d = layers[std::size_t(r)].depth[i];
        if (d < best) {
            best = d;
            ranks = {r};
        } else if (d == best && d < kInf) {
            ranks.push_back(r);
        }
    }
    return ranks;
}

// Every rank's layer, regenerated locally.
template <class Make>
std::vector<FrameImages> allLayers(Make make) {
    std::vector<FrameImages> layers;
    for (int r = 0; r < mpi().size(); ++r) layers.push_back(make(r));
    return layers;
}

bool sameBits(const float* a, const float* b, std::size_t n) {
    return std::memcmp(a, b, n * sizeof(float)) == 0;
}

// The first-surface buffers (depth, normal, id, ao) of `out` at pixel i are exactly those of one
// rank in `nearest` (rank 0's own, i.e. the background, when empty); returns that rank or -1.
int aovSource(const FrameImages& out, const std::vector<FrameImages>& layers, const std::vector<int>& nearest,
              std::size_t i) {
    std::vector<int> candidates = nearest.empty() ? std::vector<int>{0} : nearest;
    for (int r : candidates) {
        const FrameImages& l = layers[std::size_t(r)];
        if (bitsOf(out.depth[i]) == bitsOf(l.depth[i]) && sameBits(&out.normal[3 * i], &l.normal[3 * i], 3) &&
            out.id[i] == l.id[i] && (out.ao.empty() || bitsOf(out.ao[i]) == bitsOf(l.ao[i]))) {
            return r;
        }
    }
    return -1;
}

void checkOpaque(bool ao) {
    MpiSession& s = mpi();
    IcetCompositor compositor(s, kW, kH);
    FrameImages images = opaqueLayer(s.rank(), ao);
    CpuStageTimer timer;
    compositor.composite(images, CompositeMode::Opaque, {}, timer);
    ASSERT_EQ(timer.stages().size(), 1u);
    EXPECT_EQ(timer.stages()[0].stage, "composite");
    EXPECT_EQ(timer.stages()[0].items, std::uint64_t(kW * kH));
    EXPECT_EQ(compositor.lastStats().passes, ao ? 3 : 2);
    if (!s.isRoot()) return;

    std::vector<FrameImages> layers = allLayers([&](int r) { return opaqueLayer(r, ao); });
    int ties = 0, background = 0;
    for (std::size_t i = 0; i < images.pixelCount(); ++i) {
        std::vector<int> nearest = nearestRanks(layers, i);
        int source = aovSource(images, layers, nearest, i);
        ASSERT_GE(source, 0) << "pixel " << i << ": depth/normal/id/ao of no nearest rank";
        // The colour comes from the same rank as the AOVs, bit for bit.
        EXPECT_TRUE(sameBits(&images.rgba[4 * i], &layers[std::size_t(source)].rgba[4 * i], 4)) << "pixel " << i;
        ties += nearest.size() > 1;
        background += nearest.empty();
    }
    EXPECT_GT(background, 0);
    if (s.size() > 1) {
        EXPECT_GT(ties, 0);
    }
}

TEST(Compositor, depth_key_preserves_order_and_bits) {
    EXPECT_EQ(cli::depthKey(kInf), 1.0f);
    EXPECT_EQ(cli::depthKey(std::numeric_limits<float>::quiet_NaN()), 1.0f);
    EXPECT_EQ(cli::viewDepthOfKey(1.0f), kInf);
    float previousKey = 0.0f;
    // Every 4099th float from 2^-63 up to 2^63: each maps into (0, 1), strictly increasing, back to
    // itself.
    for (std::uint32_t u = bitsOf(0x1p-63f); u < bitsOf(0x1p63f); u += 4099) {
        float d;
        std::memcpy(&d, &u, sizeof d);
        float key = cli::depthKey(d);
        ASSERT_GT(key, previousKey) << d;
        ASSERT_LT(key, 1.0f) << d;
        ASSERT_EQ(bitsOf(cli::viewDepthOfKey(key)), bitsOf(d)) << d;
        previousKey = key;
    }
    EXPECT_EQ(cli::depthKey(0.0f), cli::depthKey(0x1p-63f));  // clamped below the range
    EXPECT_LT(cli::depthKey(0x1p70f), 1.0f);                  // and above it, but never background
}

TEST(Compositor, opaque_takes_every_buffer_from_the_nearest_rank_bit_for_bit) {
    checkOpaque(false);
}

TEST(Compositor, opaque_with_ambient_occlusion_takes_ao_from_the_nearest_rank) {
    checkOpaque(true);
}

TEST(Compositor, transparent_equals_front_to_back_under_in_the_given_order) {
    MpiSession& s = mpi();
    const std::vector<int> order = viewOrder(s.size());
    IcetCompositor compositor(s, kW, kH);
    FrameImages images = transparentLayer(s.rank(), true);
    CpuStageTimer timer;
    compositor.composite(images, CompositeMode::Transparent, order, timer);
    if (!s.isRoot()) return;

    std::vector<FrameImages> layers = allLayers([](int r) { return transparentLayer(r, true); });
    float maxError = 0.0f;
    for (std::size_t i = 0; i < images.pixelCount(); ++i) {
        // tubecast's front-to-back "under" of premultiplied layers (core/transparent_reference.h):
        // C += (1 - A) C_layer, A += (1 - A) A_layer.
        float acc[4] = {0, 0, 0, 0};
        for (int r : order) {
            const float* l = &layers[std::size_t(r)].rgba[4 * i];
            const float t = 1.0f - acc[3];
            for (int c = 0; c < 4; ++c) acc[c] += t * l[c];
        }
        for (int c = 0; c < 4; ++c)
            maxError = std::max(maxError, std::abs(images.rgba[4 * i + std::size_t(c)] - acc[c]));
        ASSERT_GE(aovSource(images, layers, nearestRanks(layers, i), i), 0) << "pixel " << i;
    }
    // Float rounding only: IceT associates the layers in its own tree ((L0 L1)(L2 L3) for four).
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", double(maxError));
    RecordProperty("max_error", text);
    EXPECT_LE(maxError, 1e-6f);
}

TEST(Compositor, blend_operator_is_tubecasts_under_of_the_background) {
    // The front layer on the first rank of the order, a uniform premultiplied layer on the second:
    // IceT's blend must equal core's compositeUnder of that colour as a background.
    MpiSession& s = mpi();
    if (s.size() < 2) GTEST_SKIP() << "needs two ranks";
    const std::vector<int> order = viewOrder(s.size());
    const glm::vec4 backgroundSrgb(0.2f, 0.55f, 0.9f, 0.8f);
    IcetCompositor compositor(s, kW, kH);
    FrameImages images;
    images.allocate(kW, kH);
    if (s.rank() == order[0]) {
        images = transparentLayer(s.rank(), false);
    } else if (s.rank() == order[1]) {
        const glm::vec3 bg = srgbToLinear(glm::vec3(backgroundSrgb)) * backgroundSrgb.w;
        for (std::size_t i = 0; i < images.pixelCount(); ++i) {
            images.rgba[4 * i + 0] = bg.x;
            images.rgba[4 * i + 1] = bg.y;
            images.rgba[4 * i + 2] = bg.z;
            images.rgba[4 * i + 3] = backgroundSrgb.w;
        }
    }
    CpuStageTimer timer;
    compositor.composite(images, CompositeMode::Transparent, order, timer);
    if (!s.isRoot()) return;
    FrameImages expected = transparentLayer(order[0], false);
    compositeUnder(expected, backgroundSrgb);
    for (std::size_t k = 0; k < expected.rgba.size(); ++k) {
        ASSERT_NEAR(images.rgba[k], expected.rgba[k], 1e-6f) << "float " << k;
    }
}

TEST(Compositor, region_order_decides_which_colour_is_in_front) {
    // Two nearly opaque layers, red on one rank and green on another, covering the whole image:
    // front to back in one order the image is red, in the other green.
    MpiSession& s = mpi();
    if (s.size() < 2) GTEST_SKIP() << "needs two ranks";
    const int red = s.size() - 1, green = 0;
    auto layer = [&](int r) {
        FrameImages img;
        img.allocate(kW, kH);
        for (std::size_t i = 0; r == red || r == green ? i < img.pixelCount() : false; ++i) {
            img.rgba[4 * i + (r == red ? 0 : 1)] = 0.9f;
            img.rgba[4 * i + 3] = 0.9f;
            img.depth[i] = r == red ? 2.0f : 1.0f;
        }
        return img;
    };
    std::vector<int> redFirst = {red, green}, greenFirst = {green, red};
    for (int r = 1; r < red; ++r) {
        redFirst.push_back(r);
        greenFirst.push_back(r);
    }
    IcetCompositor compositor(s, kW, kH);
    CpuStageTimer timer;
    FrameImages a = layer(s.rank());
    compositor.composite(a, CompositeMode::Transparent, redFirst, timer);
    FrameImages b = layer(s.rank());
    compositor.composite(b, CompositeMode::Transparent, greenFirst, timer);
    if (!s.isRoot()) return;
    for (std::size_t i = 0; i < a.pixelCount(); ++i) {
        // 0.9 in front, 0.1 * 0.9 of the one behind; alpha 1 - 0.1 * 0.1.
        ASSERT_NEAR(a.rgba[4 * i + 0], 0.9f, 1e-6f);
        ASSERT_NEAR(a.rgba[4 * i + 1], 0.09f, 1e-6f);
        ASSERT_NEAR(b.rgba[4 * i + 0], 0.09f, 1e-6f);
        ASSERT_NEAR(b.rgba[4 * i + 1], 0.9f, 1e-6f);
        ASSERT_NEAR(a.rgba[4 * i + 3], 0.99f, 1e-6f);
        // The first surface is green's (depth 1) whatever the blending order.
        ASSERT_EQ(a.depth[i], 1.0f);
        ASSERT_EQ(b.depth[i], 1.0f);
    }
}

TEST(Compositor, every_rank_throws_when_the_ranks_disagree) {
    MpiSession& s = mpi();
    IcetCompositor compositor(s, kW, kH);
    CpuStageTimer timer;
    FrameImages images = opaqueLayer(s.rank(), s.rank() == 0);  // only rank 0 has ao
    if (s.size() > 1) {
        EXPECT_THROW(compositor.composite(images, CompositeMode::Opaque, {}, timer), Error);
    }
    FrameImages wrongSize;
    wrongSize.allocate(s.isRoot() ? kW + 1 : kW, kH);
    EXPECT_THROW(compositor.composite(wrongSize, CompositeMode::Opaque, {}, timer), Error);
    std::vector<int> notAPermutation(std::size_t(s.size()), 0);
    notAPermutation.push_back(0);
    FrameImages fine = opaqueLayer(s.rank(), false);
    EXPECT_THROW(compositor.composite(fine, CompositeMode::Transparent, notAPermutation, timer), Error);
    // And the compositor still works afterwards.
    EXPECT_NO_THROW(compositor.composite(fine, CompositeMode::Opaque, {}, timer));
}

}  // namespace
}  // namespace tc::test
