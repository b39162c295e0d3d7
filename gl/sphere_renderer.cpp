#include "gl/sphere_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/particle_series.h"
#include "core/particle_styling.h"
#include "core/sphere_glyph.h"
#include "gl/bindings.h"
#include "gl/frame_uniforms.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"
#include "gl/sphere_ambient.h"
#include "gl/techniques.h"

namespace tc::gl {

namespace {

constexpr GLuint kSortGroupSize = 64;  // local_size_x of shaders/sphere_sort_keys.comp

const char* densityName(SphereDensity d) {
    switch (d) {
        case SphereDensity::Constant:
            return "constant";
        case SphereDensity::L2:
            return "l2";
        case SphereDensity::HollowConstant:
            return "hollow_constant";
        case SphereDensity::HollowL2:
            return "hollow_l2";
    }
    return "?";
}

template <class T>
Buffer uploadVector(const std::vector<T>& v) {
    return makeBuffer(v.size() * sizeof(T), v.data(), 0);
}

}  // namespace

SphereRenderer::~SphereRenderer() = default;

PixelBuffers SphereRenderer::pixelBuffers(const Scene& scene) {
    const bool opaque = scene.render.transparency == Transparency::Opaque;
    const std::size_t blend = opaque ? 0 : 16 + 4;  // resize(): the blend colour and depth
    return {16 + 16 + 4 + 4 + blend, 0, opaque ? "opaque spheres" : "transparent spheres"};
}

std::unique_ptr<SphereRenderer> SphereRenderer::create(const Scene& scene, const StyledParticles& particles,
                                                       const RegionSetup& region) {
    const RenderSpec& rs = scene.render;
    requireTechnique(spheresTechnique(), scene, DataKind::Particles);
    std::unique_ptr<SphereRenderer> r(new SphereRenderer());
    r->m_region = region;
    if (region.clips()) r->m_defines.push_back("REGION_CLIP");
    r->m_opaque = rs.transparency == Transparency::Opaque;
    r->m_aovs = scene.output.aovDepth || scene.output.aovNormal || scene.output.aovId;
    r->m_spheres = rs.spheres;
    r->m_lighting = scene.lighting;
    if (rs.ao.enabled) {
        r->m_ambient = std::make_unique<SphereAmbient>(
            SphereAmbient::create(rs.ao, rs.ao.cache != AoSpec::Cache::None, rs.spheres.ambient));
        r->m_defines.push_back("AMBIENT_OCCLUSION");
        if (r->m_ambient->cached()) r->m_defines.push_back("AMBIENT_CACHE");
    }
    if (rs.spheres.points) {
        r->m_pointPrograms = r->compilePrograms(true);
        GLfloat range[2] = {1.0f, 1.0f};
        glGetFloatv(GL_POINT_SIZE_RANGE, range);
        r->m_maxPointSize = range[1];
        r->m_oversized = makeBuffer(sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
    } else {
        r->m_quadPrograms = r->compilePrograms(false);
    }
    if (!r->m_opaque) {
        r->m_earlyZProgram =
            compileProgram({{GL_VERTEX_SHADER, "fullscreen.vert"}, {GL_FRAGMENT_SHADER, "sphere_early_z.frag"}});
        r->m_sortKeyProgram = compileProgram({{GL_COMPUTE_SHADER, "sphere_sort_keys.comp"}});
        r->m_radixSort = RadixSort::create();
    }
    r->m_emptyVao = VertexArray::create();
    r->m_quads = QuadIndices::create();
    r->m_quads.attachTo(r->m_emptyVao);
    r->m_samplesQuery = Query::create(GL_SAMPLES_PASSED);
    r->uploadBuffers(particles);
    r->resize(scene.image.width, scene.image.height);
    return r;
}

SphereRenderer::Programs SphereRenderer::compilePrograms(bool points) const {
    Programs p;
    p.points = points;
    auto defines = m_defines;
    if (points) defines.push_back("POINTS");
    auto opaqueDefines = defines;
    opaqueDefines.push_back("OPAQUE");
    p.opaque = compileProgram({{GL_VERTEX_SHADER, "sphere_billboard.vert"}, {GL_FRAGMENT_SHADER, "sphere.frag"}},
                              opaqueDefines);
    if (!m_opaque) {
        auto sorted = defines;
        sorted.push_back("DRAW_ORDER");
        if (m_spheres.chunks > 1) sorted.push_back("EARLY_Z");
        p.transparent =
            compileProgram({{GL_VERTEX_SHADER, "sphere_billboard.vert"}, {GL_FRAGMENT_SHADER, "sphere.frag"}}, sorted);
        if (m_spheres.chunks > 1 && m_spheres.earlyZStats) {
            std::vector<std::string> countDefines = {"DRAW_ORDER"};
            if (points) countDefines.push_back("POINTS");
            p.count = compileProgram(
                {{GL_VERTEX_SHADER, "sphere_billboard.vert"}, {GL_FRAGMENT_SHADER, "sphere_count.frag"}}, countDefines);
        }
    }
    return p;
}

const SphereRenderer::Programs& SphereRenderer::quads() {
    if (!m_quadPrograms.opaque) m_quadPrograms = compilePrograms(false);
    return m_quadPrograms;
}

void SphereRenderer::uploadBuffers(const StyledParticles& particles) {
    TC_CHECK_OP(particles.size(), <=, std::size_t(std::numeric_limits<GLint>::max() / 6));
    m_count = particles.size();
    m_bounds = particles.bounds;
    m_maxRadius = particles.maxRadius;
    m_voxelsStale = true;
    m_centerRadius = uploadVector(particles.centerRadius);
    m_colors = uploadVector(particles.color);
    m_ids = uploadVector(particles.id);
    if (!m_opaque) {
        m_keys = makeBuffer(m_count * sizeof(GLuint));
        m_order = makeBuffer(m_count * sizeof(GLuint));
    }
}

void SphereRenderer::upload(const StyledParticles& particles, StageSink& timer) {
    timer.begin("upload");
    uploadBuffers(particles);
    timer.setItems(particles.size());
    timer.end();
}

void SphereRenderer::resize(int width, int height) {
    if (width == m_width && height == m_height) return;
    m_width = width;
    m_height = height;
    m_opaqueColor = makeTexture2D(GL_RGBA32F, width, height);
    m_normalDepth = makeTexture2D(GL_RGBA32F, width, height);
    m_id = makeTexture2D(GL_R32UI, width, height);
    m_opaqueDepth = makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
    m_opaqueTarget = makeFramebuffer({&m_opaqueColor, &m_normalDepth, &m_id}, &m_opaqueDepth, "sphere opaque target");
    if (!m_opaque) {
        m_color = makeTexture2D(GL_RGBA32F, width, height);
        m_depth = makeTexture2D(GL_DEPTH_COMPONENT32F, width, height);
        m_blendTarget = makeFramebuffer({&m_color}, &m_depth, "sphere blend target");
    }
}

void SphereRenderer::setFrame(const FrameSetup& setup) {
    const Camera& cam = setup.camera;
    FrameUniforms u = frameUniforms(setup, m_lighting);
    // Linear depth for the opaque depth test: beyond everything the data can reach.
    const Bounds& bounds = m_region.boundsOr(m_bounds);
    u.farDepth =
        glm::distance(cam.eye, bounds.center()) + bounds.radius() + 2.0f * m_region.maxRadiusOr(m_maxRadius) + 1e-6f;
    setRegionUniforms(u, m_region.box);
    uploadFrameUniforms(m_frameUniforms, u);
}

void SphereRenderer::setUniforms(GLuint p) const {
    glProgramUniform1i(p, uniformLocation(p, "uDensityModel"), int(m_spheres.density));
    glProgramUniform1f(p, uniformLocation(p, "uInnerRatio"), m_spheres.innerRadius);
    glProgramUniform1f(p, uniformLocation(p, "uNormalisation"),
                       densityNormalisation(m_spheres.density, m_spheres.innerRadius));
    glProgramUniform1f(p, uniformLocation(p, "uAlphaRv"), m_spheres.alphaRv);
    glProgramUniform1f(p, uniformLocation(p, "uAlphaA"), m_ambient ? m_spheres.alphaA : 0.0f);
    glProgramUniform1f(p, uniformLocation(p, "uMaxPointSize"), m_maxPointSize);
    if (m_ambient) m_ambient->apply(p);
}

void SphereRenderer::drawRange(const Programs& programs, std::size_t first, std::size_t count) const {
    if (count == 0) return;
    glBindVertexArray(m_emptyVao.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereCenterRadius, m_centerRadius.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereColors, m_colors.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereIds, m_ids.id());
    if (m_order) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereDrawOrder, m_order.id());
    if (programs.points) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereOversized, m_oversized.id());
        glEnable(GL_PROGRAM_POINT_SIZE);
        glDrawArrays(GL_POINTS, GLint(first), GLsizei(count));
        glDisable(GL_PROGRAM_POINT_SIZE);
    } else {
        m_quads.draw(first, count);
    }
}

void SphereRenderer::sort(StageSink& timer) {
    timer.begin("sort");
    const GLuint p = m_sortKeyProgram.id();
    glProgramUniform1ui(p, uniformLocation(p, "uCount"), GLuint(m_count));
    glUseProgram(p);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereCenterRadius, m_centerRadius.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereSortKeys, m_keys.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSphereSortValues, m_order.id());
    dispatchItems(p, "uFirst", 0, m_count, kSortGroupSize);
    glUseProgram(0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    m_radixSort->sort(m_keys, m_order, m_count);
    timer.setItems(m_count);
    timer.end();
}

void SphereRenderer::renderOpaque(const FrameSetup& setup, const Programs& programs, Framebuffer& target,
                                  StageSink& timer, const std::string& stage) {
    timer.begin(stage);
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, setup.width, setup.height);
    const float zero[4] = {0, 0, 0, 0};
    const float background[4] = {0, 0, 0, std::numeric_limits<float>::infinity()};
    const GLuint noId[4] = {kBackgroundId, 0, 0, 0};
    const float far = 1.0f;
    glClearNamedFramebufferfv(target.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(target.id(), GL_COLOR, 1, background);
    glClearNamedFramebufferuiv(target.id(), GL_COLOR, 2, noId);
    glClearNamedFramebufferfv(target.id(), GL_DEPTH, 0, &far);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    const GLuint p = programs.opaque.id();
    setUniforms(p);
    glUseProgram(p);
    drawRange(programs, 0, m_count);
    glDisable(GL_DEPTH_TEST);
    timer.setItems(m_count);
    timer.end();
}

void SphereRenderer::renderTransparent(const FrameSetup& setup, const Programs& programs, StageSink& timer,
                                       const std::string& suffix) {
    const int chunks = int(std::min<std::size_t>(std::size_t(m_spheres.chunks), std::max<std::size_t>(m_count, 1)));
    const GLuint p = programs.transparent.id();
    setUniforms(p);
    const GLuint mark = m_earlyZProgram.id();
    glProgramUniform1f(mark, uniformLocation(mark, "uThreshold"), m_spheres.earlyZThreshold);

    std::uint64_t total = 0;
    if (programs.count) {
        // Every billboard fragment, for the skipped count: rasterization only, no colour, no depth.
        setUniforms(programs.count.id());
        timer.begin("count_fragments" + suffix);
        // llvmpipe skips draws that write nothing (colour writes off) without counting their
        // samples: write, but blend with (ZERO, ONE) so the target does not change.
        glBindFramebuffer(GL_FRAMEBUFFER, m_blendTarget.id());
        glViewport(0, 0, setup.width, setup.height);
        glDisable(GL_DEPTH_TEST);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ZERO, GL_ONE);
        glBeginQuery(GL_SAMPLES_PASSED, m_samplesQuery.id());
        glUseProgram(programs.count.id());
        drawRange(programs, 0, m_count);
        glEndQuery(GL_SAMPLES_PASSED);
        glDisable(GL_BLEND);
        GLuint64 n = 0;
        glGetQueryObjectui64v(m_samplesQuery.id(), GL_QUERY_RESULT, &n);
        total = n;
        timer.setItems(total);
        timer.end();
    }

    timer.begin("spheres" + suffix);
    glBindFramebuffer(GL_FRAMEBUFFER, m_blendTarget.id());
    glViewport(0, 0, setup.width, setup.height);
    const float zero[4] = {0, 0, 0, 0};
    const float far = 1.0f;
    glClearNamedFramebufferfv(m_blendTarget.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(m_blendTarget.id(), GL_DEPTH, 0, &far);
    glDisable(GL_CULL_FACE);
    // Front-to-back "under" compositing of premultiplied colour: dst += (1 - dst.a) * src.
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
    // Particle fragments sit at depth 0.5 and never write depth; the early-z mask is depth 0.
    glDepthFunc(GL_LESS);
    // One occlusion query per chunk, read after the loop (no stall between chunks).
    while (m_chunkQueries.size() < std::size_t(chunks)) m_chunkQueries.push_back(Query::create(GL_SAMPLES_PASSED));
    for (int c = 0; c < chunks; ++c) {
        const std::size_t first = m_count * std::size_t(c) / std::size_t(chunks);
        const std::size_t end = m_count * std::size_t(c + 1) / std::size_t(chunks);
        if (chunks > 1) glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        glEnable(GL_BLEND);
        glUseProgram(p);
        glBeginQuery(GL_SAMPLES_PASSED, m_chunkQueries[std::size_t(c)].id());
        drawRange(programs, first, end - first);
        glEndQuery(GL_SAMPLES_PASSED);
        if (c + 1 < chunks) {
            // Mark saturated pixels: the colour target is read as a texture while attached (not
            // written: colour writes off), which glTextureBarrier makes defined.
            glTextureBarrier();
            glDisable(GL_BLEND);
            glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
            glDepthMask(GL_TRUE);
            glDepthFunc(GL_ALWAYS);
            glUseProgram(mark);
            glBindTextureUnit(binding::kEarlyZAccumulated, m_color.id());
            glBindVertexArray(m_emptyVao.id());
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glDepthFunc(GL_LESS);
            glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        }
    }
    for (int c = 0; c < chunks; ++c) {
        GLuint64 n = 0;
        glGetQueryObjectui64v(m_chunkQueries[std::size_t(c)].id(), GL_QUERY_RESULT, &n);
        m_lastShaded += n;
    }
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    timer.setItems(m_count);
    timer.end();
    if (programs.count) {
        m_lastSkipped = total > m_lastShaded ? total - m_lastShaded : 0;
        timer.begin("early_z" + suffix);
        timer.setItems(m_lastSkipped);
        timer.end();
    }
}

void SphereRenderer::drawFrame(const FrameSetup& setup, const Programs& programs, StageSink& timer,
                               const std::string& suffix) {
    m_lastShaded = 0;
    m_lastSkipped = 0;
    if (m_opaque) {
        renderOpaque(setup, programs, m_opaqueTarget, timer, "spheres" + suffix);
    } else {
        renderTransparent(setup, programs, timer, suffix);
        if (m_aovs) renderOpaque(setup, programs, m_opaqueTarget, timer, "aovs" + suffix);
    }
}

void SphereRenderer::render(const FrameSetup& setup, FrameImages& out, StageSink& timer) {
    resize(setup.width, setup.height);
    setFrame(setup);
    const int w = setup.width, h = setup.height;
    if (m_ambient && m_voxelsStale) {
        // Once per data frame (the paper's dynamic-data timings voxelize every frame).
        timer.begin("voxelize");
        m_ambient->voxelize(m_centerRadius, m_colors, m_count, m_region.boundsOr(m_bounds), m_region);
        timer.setItems(m_count);
        timer.end();
        m_voxelsStale = false;
    }
    if (!m_opaque && m_count > 0) sort(timer);
    const bool points = bool(m_pointPrograms.opaque);
    if (points) {
        const GLuint zero = 0;
        glClearNamedBufferData(m_oversized.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    drawFrame(setup, points ? m_pointPrograms : quads(), timer, "");
    m_lastUsedQuads = !points;
    if (points) {
        // Waits for the draws (llvmpipe rasterizes the opaque pass here).
        timer.begin("point_size_check");
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        GLuint oversized = 0;
        glGetNamedBufferSubData(m_oversized.id(), 0, sizeof(GLuint), &oversized);
        timer.setItems(oversized);
        timer.end();
        if (oversized > 0) {
            // Some sphere covers more pixels than a point sprite can (close to the camera): the
            // whole frame again with two triangles per particle, timed as stages "..._quads".
            drawFrame(setup, quads(), timer, "_quads");
            m_lastUsedQuads = true;
        }
    }

    timer.begin("readback");
    const std::size_t n = std::size_t(w) * std::size_t(h);
    out.width = w;
    out.height = h;
    out.rgba.resize(4 * n);
    readTextureFlipped(m_opaque ? m_opaqueColor.id() : m_color.id(), GL_RGBA, GL_FLOAT, w, h, 4, sizeof(float),
                       out.rgba.data());
    if (m_opaque || m_aovs) {
        std::vector<float> normalDepth(4 * n);
        readTextureFlipped(m_normalDepth.id(), GL_RGBA, GL_FLOAT, w, h, 4, sizeof(float), normalDepth.data());
        out.depth.resize(n);
        out.normal.resize(3 * n);
        for (std::size_t i = 0; i < n; ++i) {
            out.depth[i] = normalDepth[4 * i + 3];
            for (int c = 0; c < 3; ++c)
                out.normal[3 * i + c] = std::isinf(out.depth[i]) ? 0.0f : normalDepth[4 * i + c];
        }
        out.id.resize(n);
        readTextureFlipped(m_id.id(), GL_RED_INTEGER, GL_UNSIGNED_INT, w, h, 1, sizeof(GLuint), out.id.data());
    } else {
        out.depth.assign(n, std::numeric_limits<float>::infinity());
        out.normal.assign(3 * n, 0.0f);
        out.id.assign(n, kBackgroundId);
    }
    out.ao.clear();
    timer.end();
}

nlohmann::json SphereRenderer::describe() const {
    nlohmann::json j = {
        {"technique", "spheres"},
        {"transparency", m_opaque ? "opaque" : "object_order"},
        {"particles", m_count},
        {"billboards", "vertex shader, vertex pulling, perspective-correct sphere bounds"},
        {"primitive", m_pointPrograms.opaque ? "points (quads when a sphere exceeds the point size)" : "quads"},
        {"max_point_size", m_maxPointSize},
        {"ambient_occlusion", m_ambient ? m_ambient->describe() : nlohmann::json(false)}};
    if (!m_opaque) {
        j["density"] = densityName(m_spheres.density);
        j["inner_radius"] = m_spheres.innerRadius;
        j["alpha_rv"] = m_spheres.alphaRv;
        j["alpha_a"] = m_spheres.alphaA;
        j["sort"] = "GPU radix sort of power-distance keys";
        j["early_z"] = {{"chunks", m_spheres.chunks}, {"threshold", m_spheres.earlyZThreshold}};
    }
    return j;
}

TechniqueDescriptor spheresTechnique() {
    TechniqueDescriptor d;
    d.name = "spheres";
    d.summary =
        "particles as sphere glyphs with emission-absorption density models, sorted front to back; "
        "a line dataset as one sphere per vertex";
    d.paper = "Staib, Grottel & Gumhold 2015";
    d.backend = TechniqueBackend::Gl;
    d.data = {DataKind::Particles, DataKind::Lines};
    d.autoData = {DataKind::Particles};
    d.transparency = {Transparency::Opaque, Transparency::ObjectOrder};
    d.exactTransparency = Transparency::ObjectOrder;
    d.ao = {AoSpec::Method::ConeTraced};
    d.regionTransparency = {Transparency::Opaque, Transparency::ObjectOrder};
    d.pixelBuffers = [](const Scene& scene, DataKind) { return SphereRenderer::pixelBuffers(scene); };
    d.create = [](const Scene& scene, const TechniqueData& data,
                  const TechniqueHooks& hooks) -> std::unique_ptr<Technique> {
        const RegionSetup region = regionSetup(data, hooks);
        if (data.kind == DataKind::Lines)
            return SphereRenderer::create(scene, particlesFromLineVertices(*data.lines), region);
        return std::make_unique<ParticleSeriesTechnique>(
            scene, *data.particles, data.firstFrame,
            [&scene, region](const StyledParticles& first, ParticleSeriesTechnique::Upload& upload) {
                std::unique_ptr<SphereRenderer> r = SphereRenderer::create(scene, first, region);
                upload = [renderer = r.get()](const StyledParticles& p, StageSink& sink) { renderer->upload(p, sink); };
                return std::unique_ptr<Technique>(std::move(r));
            });
    };
    return d;
}

}  // namespace tc::gl
