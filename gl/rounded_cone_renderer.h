#pragma once
// Opaque rounded cones (Groß & Gumhold 2020, Sect. 5.1-5.2): one billboard per segment, an
// analytic ray-rounded-cone intersection per fragment writing gl_FragDepth into a G-buffer, then
// one deferred full-screen shading pass, so shading (and AO later) runs once per visible pixel.
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

class RoundedConeRenderer final : public Technique {
public:
    // Uploads the lines and compiles the programs. Needs a current context. `region`
    // (data-parallel rendering, core/region.h): each pixel shows the nearest visible point
    // (core/cpu_reference.h's rule per segment) that lies in region.box, so the regions' images
    // Z-composite to the whole frame; AO sees every rank's density through region.reduceDensity.
    static std::unique_ptr<RoundedConeRenderer> create(const Scene& scene, const StyledLines& lines,
                                                       const RegionSetup& region = {});
    // Per-pixel GPU memory for `scene`: the G-buffer, the shaded colour and AO factor, the pyramid.
    static PixelBuffers pixelBuffers(const Scene& scene);

    void render(const FrameSetup& setup, FrameImages& out, StageSink& timer) override;
    nlohmann::json describe() const override;

private:
    RoundedConeRenderer(LineGeometry geometry, GBufferPass gbuffer, std::optional<HierarchicalCulling> culling)
        : m_geometry(std::move(geometry)), m_gbuffer(std::move(gbuffer)), m_culling(std::move(culling)) {}

    LineGeometry m_geometry;
    GBufferPass m_gbuffer;
    std::optional<HierarchicalCulling> m_culling;  // render.culling: sliced sorted draw
    std::optional<SegmentOrder> m_order;           // the draw order, with culling
    LightingSpec m_lighting;
    Program m_shadingProgram;
    int m_width = 0, m_height = 0;
    std::optional<AmbientOcclusion> m_ao;
    Texture m_color;  // premultiplied linear result
    Texture m_aoFactor;
    Framebuffer m_shaded;
};

}  // namespace tc::gl
