#include "gl/gbuffer_pass.h"

#include <limits>

#include "gl/gpu_timer.h"

namespace tc::gl {

GBufferPass GBufferPass::create(const LineGeometry& geometry) {
    GBufferPass pass;
    pass.m_program = geometry.compileDrawProgram("rounded_cone_gbuffer.frag");
    return pass;
}

void GBufferPass::resize(int width, int height) {
    if (width == m_width && height == m_height) return;
    m_width = width;
    m_height = height;
    m_albedo = makeTexture2D(GL_RGBA16F, width, height);       // linear straight RGBA
    m_normalDepth = makeTexture2D(GL_RGBA32F, width, height);  // world normal xyz, view depth w
    m_id = makeTexture2D(GL_R32UI, width, height);
    m_depth = makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
    m_framebuffer = Framebuffer::create();
    glNamedFramebufferTexture(m_framebuffer.id(), GL_COLOR_ATTACHMENT0, m_albedo.id(), 0);
    glNamedFramebufferTexture(m_framebuffer.id(), GL_COLOR_ATTACHMENT1, m_normalDepth.id(), 0);
    glNamedFramebufferTexture(m_framebuffer.id(), GL_COLOR_ATTACHMENT2, m_id.id(), 0);
    glNamedFramebufferTexture(m_framebuffer.id(), GL_DEPTH_ATTACHMENT, m_depth.id(), 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glNamedFramebufferDrawBuffers(m_framebuffer.id(), 3, buffers);
    checkFramebuffer(m_framebuffer, "G-buffer");
}

void GBufferPass::render(const LineGeometry& geometry, const FrameSetup& setup, StageTimer& timer) {
    resize(setup.width, setup.height);
    timer.begin("gbuffer");
    glViewport(0, 0, setup.width, setup.height);
    glBindFramebuffer(GL_FRAMEBUFFER, m_framebuffer.id());
    const float zero[4] = {0, 0, 0, 0};
    const float normalDepthClear[4] = {0, 0, 0, std::numeric_limits<float>::infinity()};
    const GLuint idClear[4] = {kBackgroundId, 0, 0, 0};
    const float depthClear = 1.0f;
    glClearNamedFramebufferfv(m_framebuffer.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(m_framebuffer.id(), GL_COLOR, 1, normalDepthClear);
    glClearNamedFramebufferuiv(m_framebuffer.id(), GL_COLOR, 2, idClear);
    glClearNamedFramebufferfv(m_framebuffer.id(), GL_DEPTH, 0, &depthClear);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    const GLuint p = m_program.id();
    geometry.setCameraUniforms(p, setup);
    glUseProgram(p);
    geometry.draw(0, geometry.segmentCount());
    glDisable(GL_DEPTH_TEST);
    timer.setItems(geometry.segmentCount());
    timer.end();
}

void GBufferPass::readAovs(FrameImages& out) const {
    const int w = m_width, h = m_height;
    const std::size_t n = std::size_t(w) * h;
    out.width = w;
    out.height = h;
    std::vector<float> normalDepth(4 * n);
    readTextureFlipped(m_normalDepth.id(), GL_RGBA, GL_FLOAT, w, h, 4, sizeof(float), normalDepth.data());
    out.id.resize(n);
    readTextureFlipped(m_id.id(), GL_RED_INTEGER, GL_UNSIGNED_INT, w, h, 1, sizeof(GLuint), out.id.data());
    out.normal.resize(3 * n);
    out.depth.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) out.normal[3 * i + c] = normalDepth[4 * i + c];
        out.depth[i] = normalDepth[4 * i + 3];
    }
}

}  // namespace tc::gl
