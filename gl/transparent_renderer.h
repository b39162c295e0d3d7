#pragma once
// Transparent rounded cones (Groß & Gumhold 2020, Sect. 3-4): object order (sorted segments,
// plain blending), the k-buffer (sorted segments, per-pixel sorted lists of k fragments) and depth
// peeling (the exact ground truth), all blending premultiplied colour front to back with the
// "under" operator into a float target cleared to 0. Fragments come from shaders/
// transparent_fragment.glsl: one per tube entry after cap clipping (Sect. 5.4).
#include <optional>

#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/technique.h"
#include "core/technique_registry.h"
#include "gl/ambient_occlusion.h"
#include "gl/gbuffer_pass.h"
#include "gl/hierarchical_culling.h"
#include "gl/line_geometry.h"
#include "gl/objects.h"
#include "gl/segment_order.h"

namespace tc::gl {

class TransparentRenderer final : public Technique {
public:
    // `region` (data-parallel rendering, core/region.h): only the fragments whose entry point lies
    // in region.box are blended (and the AOVs are the first such surface), so the regions' images
    // composited "under" in view order are the whole frame's; AO sees every rank's density
    // through region.reduceDensity.
    static std::unique_ptr<TransparentRenderer> create(const Scene& scene, const StyledLines& lines,
                                                       const RegionSetup& region = {});
    // Per-pixel GPU memory for `scene` (resize()): the colour target; k-buffer entries and ring
    // header, or the two peeling key buffers; the AOV G-buffer when AOVs are written; the pyramid.
    static PixelBuffers pixelBuffers(const Scene& scene);

    void render(const FrameSetup& setup, FrameImages& out, StageSink& timer) override;
    nlohmann::json describe() const override;

    // Layers peeled in the last frame (depth peeling), for tests and timings.
    int lastPeelLayers() const { return m_lastPeelLayers; }

private:
    TransparentRenderer(LineGeometry geometry) : m_geometry(std::move(geometry)) {}
    void resize(int width, int height);
    // Draws every segment with `program` in the sorted order: one draw, or depth slices with
    // culling (render.culling).
    void drawSorted(GLuint program, const FrameSetup& setup);
    void setFragmentUniforms(GLuint program, const FrameSetup& setup) const;
    void renderObjectOrder(const FrameSetup& setup, StageSink& timer);
    void renderKBuffer(const FrameSetup& setup, StageSink& timer);
    void renderDepthPeeling(const FrameSetup& setup, StageSink& timer);

    Transparency m_mode = Transparency::KBuffer;
    int m_k = 8;
    bool m_capClipping = true;
    int m_maxPeelLayers = 0;
    std::size_t m_memoryBudgetBytes = 0;
    LightingSpec m_lighting;
    std::string m_synchronisation;  // which ordering guarantee the per-pixel lists rely on

    LineGeometry m_geometry;
    std::optional<AmbientOcclusion> m_ao;
    std::optional<GBufferPass> m_gbuffer;          // for the depth / normal / id AOVs, when requested
    std::optional<SegmentOrder> m_order;           // object order and k-buffer
    std::optional<HierarchicalCulling> m_culling;  // render.culling (object order and k-buffer)

    Program m_blendProgram, m_resolveProgram, m_peelMinProgram, m_peelShadeProgram;
    VertexArray m_emptyVao;
    int m_width = 0, m_height = 0;
    Texture m_color;
    Texture m_cullDepth;  // culling: pixels the slices so far hide (gl/hierarchical_culling.h)
    Framebuffer m_framebuffer;
    Buffer m_kbuffer, m_kbufferHeaders, m_peelKeys[2], m_candidates;
    int m_lastPeelLayers = 0;
};

}  // namespace tc::gl
