#include "gl/gbuffer_pass.h"

#include <limits>

#include "core/error.h"
#include "gl/bindings.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/hierarchical_culling.h"
#include "gl/segment_order.h"
#include "gl/shader_library.h"

namespace tc::gl {

GBufferPass GBufferPass::create(const LineGeometry& geometry, const HierarchicalCulling* culling) {
    GBufferPass pass;
    pass.m_visibilityProgram = geometry.compileDrawProgram(
        "rounded_cone_gbuffer.frag", culling ? culling->drawDefines() : std::vector<std::string>{});
    std::vector<std::string> attributeDefines = geometry.regionDefines();
    attributeDefines.push_back("FULLSCREEN_FRAME_VARYINGS");
    pass.m_attributesProgram = compileProgram(
        {{GL_VERTEX_SHADER, "fullscreen.vert"}, {GL_FRAGMENT_SHADER, "surface_attributes.frag"}}, attributeDefines);
    pass.m_emptyVao = VertexArray::create();
    return pass;
}

void GBufferPass::resize(int width, int height) {
    if (width == m_width && height == m_height) return;
    m_width = width;
    m_height = height;
    m_segments = makeTexture2D(GL_R32UI, width, height);
    m_depth = makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
    m_visibility = makeFramebuffer({&m_segments}, &m_depth, "visibility buffer");

    m_albedo = makeTexture2D(GL_RGBA16F, width, height);       // linear straight RGBA
    m_normalDepth = makeTexture2D(GL_RGBA32F, width, height);  // world normal xyz, view depth w
    m_id = makeTexture2D(GL_R32UI, width, height);
    m_attributes = makeFramebuffer({&m_albedo, &m_normalDepth, &m_id}, nullptr, "surface attributes");
}

void GBufferPass::render(const LineGeometry& geometry, const FrameSetup& setup, StageSink& timer,
                         HierarchicalCulling* culling, const SegmentOrder* order) {
    resize(setup.width, setup.height);
    timer.begin("gbuffer");
    glViewport(0, 0, setup.width, setup.height);
    glBindFramebuffer(GL_FRAMEBUFFER, m_visibility.id());
    const GLuint noSegment[4] = {kBackgroundId, 0, 0, 0};
    const float depthClear = 1.0f;
    glClearNamedFramebufferuiv(m_visibility.id(), GL_COLOR, 0, noSegment);
    glClearNamedFramebufferfv(m_visibility.id(), GL_DEPTH, 0, &depthClear);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    const GLuint p = m_visibilityProgram.id();
    if (culling) {
        TC_CHECK(order);
        culling->drawSliced(geometry, *order, p, m_depth, setup);
    } else {
        glUseProgram(p);
        geometry.draw(0, geometry.segmentCount());
    }
    glDisable(GL_DEPTH_TEST);
    timer.setItems(geometry.segmentCount());
    timer.end();
    if (culling) culling->readCulled(timer);

    timer.begin("surface");
    glBindFramebuffer(GL_FRAMEBUFFER, m_attributes.id());
    const GLuint a = m_attributesProgram.id();
    glUseProgram(a);
    geometry.bind();
    glBindTextureUnit(binding::kVisibilitySegments, m_segments.id());
    glBindVertexArray(m_emptyVao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    timer.end();
}

void GBufferPass::readAovs(FrameImages& out) const {
    out.width = m_width;
    out.height = m_height;
    readNormalDepthId(m_normalDepth.id(), m_id.id(), m_width, m_height, out);
}

}  // namespace tc::gl
