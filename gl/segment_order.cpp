#include "gl/segment_order.h"

#include <cmath>

#include "gl/bindings.h"
#include "gl/gpu_timer.h"

namespace tc::gl {

SegmentOrder SegmentOrder::create(ResortPolicy policy, const CullingSpec& culling, const glm::vec3& centre,
                                  bool frustumTest) {
    SegmentOrder order(SegmentSortKeys::create(), RadixSort::create());
    order.m_policy = policy;
    order.m_frustumTest = frustumTest;
    order.m_resortCos = std::cos(glm::radians(culling.resortAngleDeg));
    order.m_resortDistance = culling.resortDistance;
    order.m_centre = centre;
    return order;
}

bool SegmentOrder::needsSort(const Camera& cam) const {
    if (!m_sortedFor) return true;
    const Camera& last = *m_sortedFor;
    if (last.projection != cam.projection) return true;
    if (m_policy == ResortPolicy::EveryChange)
        // The order depends on the eye (and on the view direction for orthographic cameras).
        return last.eye != cam.eye || last.target != cam.target;
    const float lastDistance = glm::distance(last.eye, m_centre);
    if (glm::distance(last.eye, cam.eye) > m_resortDistance * lastDistance) return true;
    const glm::vec3 a =
        cam.projection == Projection::Orthographic ? last.forward() : glm::normalize(m_centre - last.eye);
    const glm::vec3 b = cam.projection == Projection::Orthographic ? cam.forward() : glm::normalize(m_centre - cam.eye);
    return glm::dot(a, b) < m_resortCos;
}

bool SegmentOrder::sortedForView(const FrameSetup& setup) const {
    if (!m_sortedFor) return false;
    const Camera& a = *m_sortedFor;
    const Camera& b = setup.camera;
    return a.eye == b.eye && a.target == b.target && a.up == b.up && a.fovYDeg == b.fovYDeg &&
           a.projection == b.projection && a.orthoHeight == b.orthoHeight &&
           m_sortedImageSize ==
               glm::ivec2(fullWidthOf(setup.window, setup.width), fullHeightOf(setup.window, setup.height));
}

bool SegmentOrder::update(const LineGeometry& geometry, const FrameSetup& setup, StageSink& timer) {
    const Camera& cam = setup.camera;
    if (!needsSort(cam)) return false;
    timer.begin("sort");
    const std::size_t n = geometry.segmentCount();
    const glm::ivec2 imageSize(fullWidthOf(setup.window, setup.width), fullHeightOf(setup.window, setup.height));
    std::optional<ViewFrustum> frustum;
    if (m_frustumTest) frustum = viewFrustum(cam, imageSize.x, imageSize.y, kFrustumMarginPixels);
    m_keys.compute(geometry.positionRadiusBuffer(), geometry.segmentVerticesBuffer(), n, cam.eye,
                   cam.projection == Projection::Orthographic, cam.forward(), m_keyBuffer, m_drawOrder,
                   frustum ? &*frustum : nullptr);
    // Opaque culling only needs near-to-far roughly (any order gives the same image): the top 16
    // key bits (sign, exponent and 7 mantissa bits of the distance, buckets of < 1 % of it) halve
    // the radix passes. Transparent blending needs the exact order.
    m_radixSort.sort(m_keyBuffer, m_drawOrder, n, m_policy == ResortPolicy::LargeChange ? 16 : 0);
    timer.setItems(n);
    timer.end();
    m_inView = n;
    if (frustum) {
        timer.begin("frustum");
        const std::size_t outside = m_keys.outsideCount();
        m_inView = n - outside;
        timer.setItems(outside);
        timer.end();
    }
    m_sortedFor = cam;
    m_sortedImageSize = imageSize;
    ++m_sorts;
    return true;
}

void SegmentOrder::bind() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kDrawOrder, m_drawOrder.id());
}

}  // namespace tc::gl
