#pragma once
// What a technique produces for one frame: full-resolution buffers, row 0 = top of the image.
#include <cstdint>
#include <limits>
#include <vector>

namespace tc {

constexpr std::uint32_t kBackgroundId = 0xFFFFFFFFu;

// Which first-surface AOVs (depth, normal, id) a FrameImages holds. One that nobody reads (no EXR
// channel, no depth compositing) is left empty: at 1920x1080 the three are 41 MB of stores per
// frame, a few percent of a ray-traced frame (docs/performance.md, "Design notes").
struct KeptAovs {
    bool depth = true, normal = true, id = true;
};

struct FrameImages {
    int width = 0;
    int height = 0;
    std::vector<float> rgba;    // linear, premultiplied, 4 per pixel
    std::vector<float> depth;   // view-space depth of the first visible surface; +inf = background
    std::vector<float> normal;  // world-space unit normal of the first visible surface, 3 per pixel (0 on background)
    std::vector<std::uint32_t> id;  // polyline / particle index of the first visible surface; kBackgroundId
    std::vector<float> ao;          // optional (ambient occlusion), empty when not rendered

    void allocate(int w, int h) {
        width = w;
        height = h;
        std::size_t n = std::size_t(w) * std::size_t(h);
        rgba.assign(4 * n, 0.0f);
        depth.assign(n, std::numeric_limits<float>::infinity());
        normal.assign(3 * n, 0.0f);
        id.assign(n, kBackgroundId);
        ao.clear();
    }
    // Sizes the buffers for w x h without clearing them (ao emptied): for producers that write
    // every pixel of every buffer. A FrameImages reused across frames then keeps its pages: no
    // page faults and no 72 MB fill per 1920x1080 frame. The AOVs not in `keep` are emptied
    // instead (their memory stays reserved).
    void resize(int w, int h, KeptAovs keep = {}) {
        width = w;
        height = h;
        std::size_t n = std::size_t(w) * std::size_t(h);
        rgba.resize(4 * n);
        depth.resize(keep.depth ? n : 0);
        normal.resize(keep.normal ? 3 * n : 0);
        id.resize(keep.id ? n : 0);
        ao.clear();
    }
    std::size_t pixelCount() const { return std::size_t(width) * std::size_t(height); }
};

}  // namespace tc
