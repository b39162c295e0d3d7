#include "gl/rounded_cone_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"

namespace tc::gl {

namespace {

// SSBO bindings shared with shaders/rounded_cone_gbuffer.vert.
constexpr GLuint kPositionRadiusBinding = 0;
constexpr GLuint kColorBinding = 1;
constexpr GLuint kPolylineIdBinding = 2;
constexpr GLuint kSegmentVertexBinding = 3;

template <class T>
Buffer upload(const std::vector<T>& v) {
    return makeBuffer(v.size() * sizeof(T), v.data(), 0);
}

// Reads a texture level into `dst`, flipping rows: GL's row 0 is the bottom, FrameImages' the top.
template <class T>
void readFlipped(const Texture& texture, GLenum format, GLenum type, int width, int height, int components,
                 std::vector<T>& dst) {
    std::vector<T> tmp(std::size_t(width) * height * components);
    glGetTextureImage(texture.id(), 0, format, type, GLsizei(tmp.size() * sizeof(T)), tmp.data());
    dst.resize(tmp.size());
    const std::size_t row = std::size_t(width) * components;
    for (int y = 0; y < height; ++y)
        std::memcpy(&dst[std::size_t(height - 1 - y) * row], &tmp[std::size_t(y) * row], row * sizeof(T));
}

}  // namespace

std::unique_ptr<RoundedConeRenderer> RoundedConeRenderer::create(const Scene& scene, const StyledLines& lines) {
    std::unique_ptr<RoundedConeRenderer> r(new RoundedConeRenderer());
    r->m_lighting = scene.lighting;
    r->m_segmentCount = lines.segmentCount();
    r->m_maxRadius = lines.maxRadius;
    r->m_bounds = lines.bounds;
    r->m_positionRadius = upload(lines.positionRadius);
    r->m_colors = upload(lines.color);
    r->m_polylineIds = upload(lines.polylineId);
    r->m_segmentVertices = upload(lines.segmentVertices);
    r->m_gbufferProgram = compileProgram(
        {{GL_VERTEX_SHADER, "rounded_cone_gbuffer.vert"}, {GL_FRAGMENT_SHADER, "rounded_cone_gbuffer.frag"}});
    r->m_shadingProgram =
        compileProgram({{GL_VERTEX_SHADER, "fullscreen.vert"}, {GL_FRAGMENT_SHADER, "deferred_shading.frag"}});
    r->m_emptyVao = VertexArray::create();
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
    const Camera& cam = setup.camera;
    const float aspect = float(w) / float(h);
    const glm::vec3 eye = cam.eye, fwd = cam.forward(), right = cam.right(), up = cam.trueUp();
    // Linear depth in [0,1]: view depth / far, with far beyond everything the data can reach.
    // A 32-bit float depth buffer keeps ~1e-7 relative precision over that range.
    const float farDepth =
        glm::distance(eye, m_bounds.center()) + m_bounds.radius() + 2.0f * m_maxRadius + 1e-6f;
    const glm::mat4 viewProj = projectionMatrix(cam, aspect, std::max(1e-4f * farDepth, 1e-7f), farDepth) *
                               cam.worldToCamera();
    const bool ortho = cam.projection == Projection::Orthographic;
    const float tanHalf = std::tan(glm::radians(cam.fovYDeg) * 0.5f);

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
    glUseProgram(p);
    glProgramUniformMatrix4fv(p, glGetUniformLocation(p, "uViewProj"), 1, GL_FALSE, &viewProj[0][0]);
    glProgramUniform3fv(p, glGetUniformLocation(p, "uEye"), 1, &eye[0]);
    glProgramUniform3fv(p, glGetUniformLocation(p, "uForward"), 1, &fwd[0]);
    glProgramUniform3fv(p, glGetUniformLocation(p, "uRight"), 1, &right[0]);
    glProgramUniform3fv(p, glGetUniformLocation(p, "uUp"), 1, &up[0]);
    glProgramUniform1i(p, glGetUniformLocation(p, "uOrthographic"), ortho ? 1 : 0);
    glProgramUniform1f(p, glGetUniformLocation(p, "uTanHalfFov"), tanHalf);
    glProgramUniform1f(p, glGetUniformLocation(p, "uOrthoHalfHeight"), 0.5f * cam.orthoHeight);
    glProgramUniform1f(p, glGetUniformLocation(p, "uAspect"), aspect);
    glProgramUniform2f(p, glGetUniformLocation(p, "uViewport"), float(w), float(h));
    glProgramUniform1f(p, glGetUniformLocation(p, "uFarDepth"), farDepth);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPositionRadiusBinding, m_positionRadius.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kColorBinding, m_colors.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPolylineIdBinding, m_polylineIds.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSegmentVertexBinding, m_segmentVertices.id());
    glBindVertexArray(m_emptyVao.id());
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(6 * m_segmentCount));
    timer.setItems(m_segmentCount);
    timer.end();

    timer.begin("shading");
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, m_shaded.id());
    glClearNamedFramebufferfv(m_shaded.id(), GL_COLOR, 0, zero);
    const GLuint s = m_shadingProgram.id();
    glUseProgram(s);
    const glm::vec3 lc = glm::normalize(m_lighting.direction);
    // Light direction from camera space (camera looks down -z) to world space.
    const glm::vec3 lightWorld = glm::normalize(lc.x * right + lc.y * up - lc.z * fwd);
    glProgramUniform3fv(s, glGetUniformLocation(s, "uEye"), 1, &eye[0]);
    glProgramUniform3fv(s, glGetUniformLocation(s, "uForward"), 1, &fwd[0]);
    glProgramUniform3fv(s, glGetUniformLocation(s, "uRight"), 1, &right[0]);
    glProgramUniform3fv(s, glGetUniformLocation(s, "uUp"), 1, &up[0]);
    glProgramUniform1i(s, glGetUniformLocation(s, "uOrthographic"), ortho ? 1 : 0);
    glProgramUniform1f(s, glGetUniformLocation(s, "uTanHalfFov"), tanHalf);
    glProgramUniform1f(s, glGetUniformLocation(s, "uOrthoHalfHeight"), 0.5f * cam.orthoHeight);
    glProgramUniform1f(s, glGetUniformLocation(s, "uAspect"), aspect);
    glProgramUniform2f(s, glGetUniformLocation(s, "uViewport"), float(w), float(h));
    glProgramUniform3fv(s, glGetUniformLocation(s, "uLightDir"), 1, &lightWorld[0]);
    glProgramUniform4f(s, glGetUniformLocation(s, "uLightTerms"), m_lighting.ambient, m_lighting.diffuse,
                       m_lighting.specular, m_lighting.shininess);
    glBindTextureUnit(0, m_albedo.id());
    glBindTextureUnit(1, m_normalDepth.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    timer.end();

    timer.begin("readback");
    out.width = w;
    out.height = h;
    std::vector<float> normalDepth;
    readFlipped(m_color, GL_RGBA, GL_FLOAT, w, h, 4, out.rgba);
    readFlipped(m_normalDepth, GL_RGBA, GL_FLOAT, w, h, 4, normalDepth);
    readFlipped(m_id, GL_RED_INTEGER, GL_UNSIGNED_INT, w, h, 1, out.id);
    const std::size_t n = std::size_t(w) * h;
    out.normal.resize(3 * n);
    out.depth.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        out.normal[3 * i + 0] = normalDepth[4 * i + 0];
        out.normal[3 * i + 1] = normalDepth[4 * i + 1];
        out.normal[3 * i + 2] = normalDepth[4 * i + 2];
        out.depth[i] = normalDepth[4 * i + 3];
    }
    out.ao.clear();
    timer.end();
}

nlohmann::json RoundedConeRenderer::describe() const {
    return {{"technique", "rasterized"},
            {"transparency", "opaque"},
            {"billboards", "vertex pulling (6 vertices per segment from SSBOs)"},
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
