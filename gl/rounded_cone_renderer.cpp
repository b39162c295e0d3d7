#include "gl/rounded_cone_renderer.h"

#include "core/error.h"
#include "gl/bindings.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"

namespace tc::gl {

std::unique_ptr<RoundedConeRenderer> RoundedConeRenderer::create(const Scene& scene, const StyledLines& lines,
                                                                 const RegionSetup& region) {
    LineGeometry geometry = LineGeometry::create(lines, scene.render.billboards, region, scene.render.billboardShape);
    std::optional<HierarchicalCulling> culling;
    if (scene.render.culling.enabled)
        culling = HierarchicalCulling::create(HierarchicalCulling::Target::MaxDepth, scene.render.culling, geometry);
    GBufferPass gbuffer = GBufferPass::create(geometry, culling ? &*culling : nullptr);
    std::unique_ptr<RoundedConeRenderer> r(
        new RoundedConeRenderer(std::move(geometry), std::move(gbuffer), std::move(culling)));
    if (r->m_culling)
        r->m_order = SegmentOrder::create(SegmentOrder::ResortPolicy::LargeChange, scene.render.culling,
                                          region.boundsOr(lines.bounds).center(), /*frustumTest=*/true);
    r->m_lighting = scene.lighting;
    std::vector<std::string> defines;
    if (scene.render.ao.enabled) {
        r->m_ao = AmbientOcclusion::create(scene.render.ao, lines, region);
        r->m_ao->buildLineCache(r->m_geometry, lines);
        defines = r->m_ao->lineDefines();
    }
    defines.push_back("FULLSCREEN_FRAME_VARYINGS");
    r->m_shadingProgram =
        compileProgram({{GL_VERTEX_SHADER, "fullscreen.vert"}, {GL_FRAGMENT_SHADER, "deferred_shading.frag"}}, defines);
    return r;
}

PixelBuffers RoundedConeRenderer::pixelBuffers(const Scene& scene) {
    const std::size_t pyramid = scene.render.culling.enabled ? HierarchicalCulling::kBytesPerPixel : 0;
    return {GBufferPass::kBytesPerPixel + 16 + 4 + pyramid, 0, "opaque G-buffer"};  // + m_color, m_aoFactor
}

void RoundedConeRenderer::render(const FrameSetup& setup, FrameImages& out, StageSink& timer) {
    const int w = setup.width, h = setup.height;
    if (w != m_width || h != m_height) {
        m_width = w;
        m_height = h;
        m_color = makeTexture2D(GL_RGBA32F, w, h);
        m_aoFactor = makeTexture2D(GL_R32F, w, h);
        m_shaded = makeFramebuffer({&m_color, &m_aoFactor}, nullptr, "shading target");
    }
    m_geometry.setFrame(setup, m_lighting);
    if (m_culling) {
        m_order->update(m_geometry, setup, timer);
        m_gbuffer.render(m_geometry, setup, timer, &*m_culling, &*m_order);
    } else {
        m_geometry.computeBillboards(timer);
        m_gbuffer.render(m_geometry, setup, timer);
    }

    timer.begin("shading");
    glBindFramebuffer(GL_FRAMEBUFFER, m_shaded.id());
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(m_shaded.id(), GL_COLOR, 0, zero);
    const GLuint s = m_shadingProgram.id();
    glUseProgram(s);
    if (m_ao) m_ao->apply(s);
    glBindTextureUnit(binding::kGBufferAlbedo, m_gbuffer.albedo().id());
    glBindTextureUnit(binding::kGBufferNormalDepth, m_gbuffer.normalDepth().id());
    glBindTextureUnit(binding::kVisibilitySegments, m_gbuffer.segments().id());
    m_geometry.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    timer.end();

    timer.begin("readback");
    out.rgba.resize(4 * std::size_t(w) * h);
    readTextureFlipped(m_color.id(), GL_RGBA, GL_FLOAT, w, h, 4, sizeof(float), out.rgba.data());
    m_gbuffer.readAovs(out);
    out.ao.clear();
    if (m_ao) {
        out.ao.resize(std::size_t(w) * h);
        readTextureFlipped(m_aoFactor.id(), GL_RED, GL_FLOAT, w, h, 1, sizeof(float), out.ao.data());
    }
    timer.end();
}

nlohmann::json RoundedConeRenderer::describe() const {
    nlohmann::json j = {{"technique", "rasterized"},
                        {"transparency", "opaque"},
                        {"billboards", m_geometry.describeBillboards()},
                        {"billboard_shape", m_geometry.describeBillboardShape()},
                        {"shading", "deferred"},
                        {"ambient_occlusion", m_ao ? m_ao->describe() : nlohmann::json(false)},
                        {"culling", m_culling ? m_culling->describe() : nlohmann::json(false)}};
    if (m_order) {
        j["sort"] = "GPU radix sort of segment distance keys, re-sorted only after large camera changes";
        j["sorts_performed"] = m_order->sortsPerformed();
    }
    return j;
}

}  // namespace tc::gl
