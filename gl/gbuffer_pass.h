#pragma once
// The G-buffer pass of the rasterized line techniques, as a visibility buffer: the draw ray-casts
// rounded cones and writes only depth (gl_FragDepth, depth-tested) and the segment id; one
// full-screen pass then re-intersects each pixel's visible segment, gives a depth tie with its
// polyline predecessors to the lowest of them (so the result does not depend on the draw order,
// which culling changes), and writes linear albedo, outward world normal + view depth, and
// polyline id. The opaque technique shades it (deferred); the transparent techniques use
// it for the depth / normal / id AOVs, which are the first surface of the union of all tubes.
#include "core/frame_images.h"
#include "gl/line_geometry.h"
#include "gl/objects.h"

namespace tc::gl {

class HierarchicalCulling;
class SegmentOrder;

class GBufferPass {
public:
    // `culling`: draw in depth slices of the sorted order and cull what is hidden (opaque path,
    // render.culling); then render() needs the order and the culling.
    static GBufferPass create(const LineGeometry& geometry, const HierarchicalCulling* culling = nullptr);

    // Per-pixel bytes of its targets (resize()): segment R32UI, depth 32F, albedo RGBA16F,
    // normal + depth RGBA32F, id R32UI.
    static constexpr std::size_t kBytesPerPixel = 4 + 4 + 8 + 16 + 4;

    // Renders the G-buffer for this frame (stage "gbuffer"). Without culling the billboards must
    // be computed; with it, `order` is the segment order and the billboards are built per slice.
    void render(const LineGeometry& geometry, const FrameSetup& setup, StageSink& timer,
                HierarchicalCulling* culling = nullptr, const SegmentOrder* order = nullptr);
    // Copies depth, normal and id into `out` (rows flipped to top-first); `out` is resized.
    void readAovs(FrameImages& out) const;

    const Texture& albedo() const { return m_albedo; }
    const Texture& normalDepth() const { return m_normalDepth; }
    const Texture& segments() const { return m_segments; }  // visible segment id (R32UI)
    int width() const { return m_width; }
    int height() const { return m_height; }

private:
    GBufferPass() = default;
    void resize(int width, int height);

    Program m_visibilityProgram, m_attributesProgram;
    VertexArray m_emptyVao;
    int m_width = 0, m_height = 0;
    Texture m_segments, m_depth, m_albedo, m_normalDepth, m_id;
    Framebuffer m_visibility, m_attributes;
};

}  // namespace tc::gl
