#pragma once
// The front-to-back segment order of the rasterized line techniques (Groß & Gumhold 2020,
// Sect. 4.1): per-segment distance keys (gl/sort_keys.h) sorted by the GPU radix sort
// (gl/radix_sort.h) into the draw-order buffer that DRAW_ORDER programs read (SSBO_DRAW_ORDER).
//
// When to sort again: transparent blending needs the order of the current eye, so any camera
// change re-sorts (ResortPolicy::EveryChange). Opaque rendering with culling only uses the order
// to find occluders early — any order gives the same image — so, as in the paper, it re-sorts
// only after a large camera change (ResortPolicy::LargeChange, render.culling.resort_*).
//
// With a frustum test (depth slices of render.culling), segments whose bounding sphere lies
// outside the view frustum of the sort's camera (core/frustum.h) get the largest key: the first
// inViewCount() segments of the order are the ones in view, front to back, and the rest cannot
// rasterize a fragment in that view, so the slices are cut from what is in view and the rest is
// not drawn (drawn as one more slice when the order is reused for another view).
#include <cstddef>
#include <optional>

#include "core/camera.h"
#include "core/scene.h"
#include "core/technique.h"
#include "gl/line_geometry.h"
#include "gl/objects.h"
#include "gl/radix_sort.h"
#include "gl/sort_keys.h"

namespace tc::gl {

class SegmentOrder {
public:
    enum class ResortPolicy { EveryChange, LargeChange };

    // `centre`: the point the LargeChange angle is measured around (the data's centre).
    // `frustumTest`: sort what lies outside the view last and count it (see above).
    static SegmentOrder create(ResortPolicy policy, const CullingSpec& culling, const glm::vec3& centre,
                               bool frustumTest = false);

    // Sorts for setup.camera as stage "sort" of `timer` if the policy asks for it; returns whether
    // it did. The first call always sorts. With the frustum test, stage "frustum" follows (items:
    // segments outside the view; its time is the wait for the key pass's count).
    bool update(const LineGeometry& geometry, const FrameSetup& setup, StageSink& timer);
    // Segments in view of the last sort's camera (all without the frustum test): the order's prefix.
    std::size_t inViewCount() const { return m_inView; }
    // Whether the last sort was for exactly this camera and full image size, so that segments
    // behind inViewCount() are outside this view.
    bool sortedForView(const FrameSetup& setup) const;
    // Binds the draw order to binding::kDrawOrder.
    void bind() const;
    const Buffer& drawOrder() const { return m_drawOrder; }
    // Sorts performed since creation (run.json, timings).
    std::size_t sortsPerformed() const { return m_sorts; }
    // Whether `camera` is far enough from the camera of the last sort to sort again.
    bool needsSort(const Camera& camera) const;
    // Pixels the frustum grows by on every side (sample jitter is at most half a pixel).
    static constexpr float kFrustumMarginPixels = 2.0f;

private:
    SegmentOrder(SegmentSortKeys keys, RadixSort sort) : m_keys(std::move(keys)), m_radixSort(std::move(sort)) {}

    SegmentSortKeys m_keys;
    RadixSort m_radixSort;
    ResortPolicy m_policy = ResortPolicy::EveryChange;
    float m_resortCos = 1.0f;       // cos(resort angle)
    float m_resortDistance = 0.0f;  // fraction of the eye's distance to m_centre
    glm::vec3 m_centre{0.0f};
    Buffer m_keyBuffer, m_drawOrder;
    std::optional<Camera> m_sortedFor;
    glm::ivec2 m_sortedImageSize{0};
    bool m_frustumTest = false;
    std::size_t m_inView = 0;
    std::size_t m_sorts = 0;
};

}  // namespace tc::gl
