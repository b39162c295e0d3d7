#include "gl/rounded_cone_renderer.h"

#include <limits>

#include "core/error.h"
#include "core/shading.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"

namespace tc::gl {

std::unique_ptr<RoundedConeRenderer> RoundedConeRenderer::create(const Scene& scene, const StyledLines& lines) {
    std::unique_ptr<RoundedConeRenderer> r(
        new RoundedConeRenderer(LineGeometry::create(lines, scene.render.billboards)));
    r->m_lighting = scene.lighting;
    r->m_gbufferProgram = r->m_geometry.compileDrawProgram("rounded_cone_gbuffer.frag");
    r->m_shadingProgram =
        compileProgram({{GL_VERTEX_SHADER, "fullscreen.vert"}, {GL_FRAGMENT_SHADER, "deferred_shading.frag"}});
    return r;
}

void RoundedConeRenderer::resizeTargets(int width, int height) {
    if (width == m_width && height == m_height) return;
    m_width = width;
    m_height = height;
    m_albedo = makeTexture2D(GL_RGBA16F, width, height);       // linear straight RGBA
    m_normalDepth = makeTexture2D(GL_RGBA32F, width, height);  // world normal xyz, view depth w
    m_id = makeTexture2D(GL_R32UI, width, height);
    m_depth = makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
    m_color = makeTexture2D(GL_RGBA32F, width, height);  // premultiplied linear result

    m_gbuffer = Framebuffer::create();
    glNamedFramebufferTexture(m_gbuffer.id(), GL_COLOR_ATTACHMENT0, m_albedo.id(), 0);
    glNamedFramebufferTexture(m_gbuffer.id(), GL_COLOR_ATTACHMENT1, m_normalDepth.id(), 0);
    glNamedFramebufferTexture(m_gbuffer.id(), GL_COLOR_ATTACHMENT2, m_id.id(), 0);
    glNamedFramebufferTexture(m_gbuffer.id(), GL_DEPTH_ATTACHMENT, m_depth.id(), 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glNamedFramebufferDrawBuffers(m_gbuffer.id(), 3, buffers);
    checkFramebuffer(m_gbuffer, "G-buffer");

    m_shaded = Framebuffer::create();
    glNamedFramebufferTexture(m_shaded.id(), GL_COLOR_ATTACHMENT0, m_color.id(), 0);
    glNamedFramebufferDrawBuffer(m_shaded.id(), GL_COLOR_ATTACHMENT0);
    checkFramebuffer(m_shaded, "shading target");
}

void RoundedConeRenderer::render(const FrameSetup& setup, FrameImages& out, StageTimer& timer) {
    const int w = setup.width, h = setup.height;
    resizeTargets(w, h);
    m_geometry.computeBillboards(setup, timer);

    timer.begin("gbuffer");
    glViewport(0, 0, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, m_gbuffer.id());
    const float zero[4] = {0, 0, 0, 0};
    const float normalDepthClear[4] = {0, 0, 0, std::numeric_limits<float>::infinity()};
    const GLuint idClear[4] = {kBackgroundId, 0, 0, 0};
    const float depthClear = 1.0f;
    glClearNamedFramebufferfv(m_gbuffer.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(m_gbuffer.id(), GL_COLOR, 1, normalDepthClear);
    glClearNamedFramebufferuiv(m_gbuffer.id(), GL_COLOR, 2, idClear);
    glClearNamedFramebufferfv(m_gbuffer.id(), GL_DEPTH, 0, &depthClear);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    const GLuint p = m_gbufferProgram.id();
    m_geometry.setCameraUniforms(p, setup);
    glUseProgram(p);
    m_geometry.draw(0, m_geometry.segmentCount());
    timer.setItems(m_geometry.segmentCount());
    timer.end();

    timer.begin("shading");
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, m_shaded.id());
    glClearNamedFramebufferfv(m_shaded.id(), GL_COLOR, 0, zero);
    const GLuint s = m_shadingProgram.id();
    m_geometry.setCameraUniforms(s, setup);
    glUseProgram(s);
    const glm::vec3 lightWorld = lightDirectionWorld(m_lighting, setup.camera);
    glProgramUniform3fv(s, uniformLocation(s, "uLightDir"), 1, &lightWorld[0]);
    glProgramUniform4f(s, uniformLocation(s, "uLightTerms"), m_lighting.ambient, m_lighting.diffuse,
                       m_lighting.specular, m_lighting.shininess);
    glBindTextureUnit(0, m_albedo.id());
    glBindTextureUnit(1, m_normalDepth.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    timer.end();

    timer.begin("readback");
    const std::size_t n = std::size_t(w) * h;
    out.width = w;
    out.height = h;
    out.rgba.resize(4 * n);
    out.id.resize(n);
    std::vector<float> normalDepth(4 * n);
    readTextureFlipped(m_color.id(), GL_RGBA, GL_FLOAT, w, h, 4, sizeof(float), out.rgba.data());
    readTextureFlipped(m_normalDepth.id(), GL_RGBA, GL_FLOAT, w, h, 4, sizeof(float), normalDepth.data());
    readTextureFlipped(m_id.id(), GL_RED_INTEGER, GL_UNSIGNED_INT, w, h, 1, sizeof(GLuint), out.id.data());
    out.normal.resize(3 * n);
    out.depth.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) out.normal[3 * i + c] = normalDepth[4 * i + c];
        out.depth[i] = normalDepth[4 * i + 3];
    }
    out.ao.clear();
    timer.end();
}

nlohmann::json RoundedConeRenderer::describe() const {
    const BillboardPath path = m_geometry.billboardPath();
    return {{"technique", "rasterized"},
            {"transparency", "opaque"},
            {"billboards", path == BillboardPath::Compute  ? "compute pre-pass, vertex pulling"
                           : path == BillboardPath::Vertex ? "vertex shader, vertex pulling"
                                                           : "geometry shader"},
            {"shading", "deferred"}};
}

std::unique_ptr<Technique> createTechnique(const Scene& scene, const StyledLines& lines) {
    switch (scene.render.technique) {
    case RenderTechnique::Rasterized:
        return RoundedConeRenderer::create(scene, lines);
    }
    throw InputError("unsupported render.technique");
}

}  // namespace tc::gl
