#include "gl/transparent_renderer.h"

#include <iostream>
#include <limits>

#include "core/error.h"
#include "gl/bindings.h"
#include "gl/context.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"

namespace tc::gl {

namespace {

void clearBuffer64(const Buffer& buffer, std::uint64_t value) {
    glClearNamedBufferData(buffer.id(), GL_RG32UI, GL_RG_INTEGER, GL_UNSIGNED_INT, &value);
}

}  // namespace

std::unique_ptr<TransparentRenderer> TransparentRenderer::create(const Scene& scene, const StyledLines& lines,
                                                                 const RegionSetup& region) {
    std::unique_ptr<TransparentRenderer> r(new TransparentRenderer(
        LineGeometry::create(lines, scene.render.billboards, region, scene.render.billboardShape)));
    const RenderSpec& rs = scene.render;
    r->m_mode = rs.transparency;
    r->m_k = rs.kbufferK;
    r->m_capClipping = rs.capClipping;
    r->m_geometry.setCapClipping(rs.capClipping);
    if (scene.style.halo.enabled) r->m_geometry.enableHalo(lineHalo(scene.style.halo, scene.image.background));
    r->m_maxPeelLayers = rs.maxPeelLayers;
    r->m_memoryBudgetBytes = std::size_t(rs.memoryBudgetMb) * 1024 * 1024;
    r->m_lighting = scene.lighting;
    if (scene.output.aovDepth || scene.output.aovNormal || scene.output.aovId)
        r->m_gbuffer = GBufferPass::create(r->m_geometry);

    // Per-pixel read-modify-write must be ordered: interlock where the GPU has it, llvmpipe's
    // in-order per-pixel shading with blending on, else a warning.
    std::vector<std::string> syncDefines;
    if (rs.ao.enabled) {
        r->m_ao = AmbientOcclusion::create(rs.ao, lines, region);
        r->m_ao->buildLineCache(r->m_geometry, lines);
        syncDefines = r->m_ao->lineDefines();
    }
    const ContextInfo& context = currentContextInfo();
    if (context.hasExtension("GL_ARB_fragment_shader_interlock")) {
        syncDefines.push_back("USE_INTERLOCK");
        r->m_synchronisation = "ARB_fragment_shader_interlock";
    } else if (context.renderer.find("llvmpipe") != std::string::npos) {
        r->m_synchronisation = "llvmpipe per-pixel primitive order (blending on)";
    } else {
        r->m_synchronisation = "none (unordered: results may race)";
        if (rs.transparency != Transparency::ObjectOrder)
            std::cerr << "warning: this GPU has no fragment shader interlock and is not llvmpipe; the "
                      << transparencyName(rs.transparency) << " per-pixel updates are not ordered and may race\n";
    }

    // Depth slices with culling apply to the sorted draws; depth peeling has no order to slice.
    std::vector<std::string> sortedDefines{"DRAW_ORDER"};
    if (rs.culling.enabled && r->m_mode != Transparency::DepthPeeling) {
        r->m_culling = HierarchicalCulling::create(HierarchicalCulling::Target::MinOpacity, rs.culling, r->m_geometry);
        sortedDefines = r->m_culling->drawDefines();
    }
    switch (r->m_mode) {
        case Transparency::ObjectOrder: {
            std::vector<std::string> defines = sortedDefines;
            if (r->m_ao)
                for (const std::string& d : r->m_ao->lineDefines()) defines.push_back(d);
            r->m_blendProgram = r->m_geometry.compileDrawProgram("object_order.frag", defines);
            break;
        }
        case Transparency::KBuffer: {
            std::vector<std::string> defines = syncDefines;
            defines.insert(defines.end(), sortedDefines.begin(), sortedDefines.end());
            defines.push_back("KBUFFER_K " + std::to_string(r->m_k));
            r->m_blendProgram = r->m_geometry.compileDrawProgram("kbuffer_insert.frag", defines);
            r->m_resolveProgram =
                compileProgram({{GL_VERTEX_SHADER, "fullscreen.vert"}, {GL_FRAGMENT_SHADER, "kbuffer_resolve.frag"}},
                               {"KBUFFER_K " + std::to_string(r->m_k)});
            break;
        }
        case Transparency::DepthPeeling: {
            std::vector<std::string> defines = syncDefines;
            if (context.hasExtension("GL_ARB_shader_atomic_int64")) {
                std::erase(defines, std::string("USE_INTERLOCK"));
                defines.push_back("USE_ATOMIC64");
                r->m_synchronisation = "ARB_shader_atomic_int64 (atomicMin)";
            }
            auto minDefines = defines, shadeDefines = defines;
            minDefines.push_back("PEEL_MIN");
            shadeDefines.push_back("PEEL_SHADE");
            r->m_peelMinProgram = r->m_geometry.compileDrawProgram("depth_peel.frag", minDefines);
            r->m_peelShadeProgram = r->m_geometry.compileDrawProgram("depth_peel.frag", shadeDefines);
            r->m_candidates = makeBuffer(sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);
            break;
        }
        case Transparency::Opaque:
        case Transparency::OpacityOptimization:  // gl/opacity_renderer.cpp
        case Transparency::Auto:                 // resolved before any technique is made
            TC_CHECK(false);
    }
    if (r->m_mode != Transparency::DepthPeeling)
        r->m_order = SegmentOrder::create(SegmentOrder::ResortPolicy::EveryChange, rs.culling,
                                          region.boundsOr(lines.bounds).center(),
                                          /*frustumTest=*/rs.culling.enabled);
    r->m_emptyVao = VertexArray::create();
    // Allocate (and check the memory budget) now, before the frame loop writes any output.
    r->resize(scene.image.width, scene.image.height);
    return r;
}

PixelBuffers TransparentRenderer::pixelBuffers(const Scene& scene) {
    const RenderSpec& r = scene.render;
    const OutputSpec& o = scene.output;
    const std::size_t aovs = o.aovDepth || o.aovNormal || o.aovId ? GBufferPass::kBytesPerPixel : 0;
    const std::size_t pyramid =
        r.culling.enabled ? HierarchicalCulling::kBytesPerPixel + HierarchicalCulling::kMarkBytesPerPixel : 0;
    switch (r.transparency) {
        case Transparency::KBuffer: {
            const std::size_t entries = 8 * std::size_t(r.kbufferK);  // m_kbuffer; + 4 B ring header
            return {16 + entries + 4 + aovs + pyramid, entries, "kbuffer with k=" + std::to_string(r.kbufferK)};
        }
        case Transparency::DepthPeeling:
            return {16 + 16 + aovs, 8, "depth_peeling"};  // + two 8 B key buffers
        default:
            return {16 + aovs + pyramid, 0, transparencyName(r.transparency)};
    }
}

void TransparentRenderer::resize(int width, int height) {
    if (width == m_width && height == m_height) return;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    std::size_t bytes = pixels * 16;                                                    // the float colour target
    if (m_mode == Transparency::KBuffer) bytes += pixels * (std::size_t(m_k) * 8 + 4);  // entries, ring header
    if (m_mode == Transparency::DepthPeeling) bytes += pixels * 16;
    if (m_culling) bytes += pixels * HierarchicalCulling::kMarkBytesPerPixel;
    if (bytes > m_memoryBudgetBytes)
        throw InputError(
            "render.memory_budget_mb: " + std::string(transparencyName(m_mode)) + " at " + std::to_string(width) + "x" +
            std::to_string(height) + (m_mode == Transparency::KBuffer ? " with k=" + std::to_string(m_k) : "") +
            " needs " + std::to_string(bytes / (1024 * 1024) + 1) + " MB of per-pixel buffers, over the budget of " +
            std::to_string(m_memoryBudgetBytes / (1024 * 1024)) + " MB (lower image size or k, or raise the budget)");
    m_width = width;
    m_height = height;
    m_color = makeTexture2D(GL_RGBA32F, width, height);
    if (m_culling) m_cullDepth = makeTexture2D(GL_DEPTH_COMPONENT16, width, height);
    m_framebuffer = makeFramebuffer({&m_color}, m_culling ? &m_cullDepth : nullptr, "transparency target");
    if (m_mode == Transparency::KBuffer) {
        m_kbuffer = makeBuffer(pixels * std::size_t(m_k) * 8);
        clearBuffer64(m_kbuffer, ~std::uint64_t(0));  // the resolve pass leaves it empty again
        m_kbufferHeaders = makeBuffer(pixels * 4);
        const GLuint zero = 0;  // head 0, count 0; the resolve pass resets it too
        glClearNamedBufferData(m_kbufferHeaders.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    }
    if (m_mode == Transparency::DepthPeeling)
        for (auto& b : m_peelKeys) b = makeBuffer(pixels * 8);
}

void TransparentRenderer::drawSorted(GLuint program, const FrameSetup& setup) {
    if (m_culling) {
        m_culling->drawSliced(m_geometry, *m_order, program, m_color, setup);
        return;
    }
    glUseProgram(program);
    m_order->bind();
    m_geometry.draw(0, m_geometry.segmentCount());
}

void TransparentRenderer::setFragmentUniforms(GLuint p, const FrameSetup& setup) const {
    glProgramUniform1ui(p, uniformLocation(p, "uImageWidth"), GLuint(setup.width));
    if (m_ao) m_ao->apply(p);
}

void TransparentRenderer::render(const FrameSetup& setup, FrameImages& out, StageSink& timer) {
    resize(setup.width, setup.height);
    m_geometry.setFrame(setup, m_lighting);
    // With culling the billboards are built per depth slice; the G-buffer pass of the AOVs
    // needs them all.
    if (!m_culling || m_gbuffer) m_geometry.computeBillboards(timer);
    if (m_gbuffer) m_gbuffer->render(m_geometry, setup, timer);
    if (m_order) m_order->update(m_geometry, setup, timer);

    beginUnderCompositing(m_framebuffer.id(), setup.width, setup.height);

    switch (m_mode) {
        case Transparency::ObjectOrder:
            renderObjectOrder(setup, timer);
            break;
        case Transparency::KBuffer:
            renderKBuffer(setup, timer);
            break;
        case Transparency::DepthPeeling:
            renderDepthPeeling(setup, timer);
            break;
        case Transparency::Opaque:
        case Transparency::OpacityOptimization:
        case Transparency::Auto:
            TC_CHECK(false);
    }
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);

    timer.begin("readback");
    const int w = setup.width, h = setup.height;
    out.width = w;
    out.height = h;
    out.rgba.resize(4 * std::size_t(w) * h);
    readTextureFlipped(m_color.id(), GL_RGBA, GL_FLOAT, w, h, 4, sizeof(float), out.rgba.data());
    if (m_gbuffer) {
        m_gbuffer->readAovs(out);
    } else {
        const std::size_t n = std::size_t(w) * h;
        out.depth.assign(n, std::numeric_limits<float>::infinity());
        out.normal.assign(3 * n, 0.0f);
        out.id.assign(n, kBackgroundId);
    }
    out.ao.clear();
    timer.end();
}

void TransparentRenderer::renderObjectOrder(const FrameSetup& setup, StageSink& timer) {
    timer.begin("blend");
    const GLuint p = m_blendProgram.id();
    setFragmentUniforms(p, setup);
    drawSorted(p, setup);
    timer.setItems(m_geometry.segmentCount());
    timer.end();
    if (m_culling) m_culling->readCulled(timer);
}

void TransparentRenderer::renderKBuffer(const FrameSetup& setup, StageSink& timer) {
    timer.begin("kbuffer");
    const GLuint p = m_blendProgram.id();
    setFragmentUniforms(p, setup);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kKBuffer, m_kbuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kKBufferHeaders, m_kbufferHeaders.id());
    drawSorted(p, setup);
    timer.setItems(m_geometry.segmentCount());
    timer.end();
    if (m_culling) m_culling->readCulled(timer);

    timer.begin("resolve");
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    const GLuint r = m_resolveProgram.id();
    glProgramUniform1ui(r, uniformLocation(r, "uImageWidth"), GLuint(setup.width));
    glUseProgram(r);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kKBuffer, m_kbuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kKBufferHeaders, m_kbufferHeaders.id());
    glBindVertexArray(m_emptyVao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    timer.end();
}

void TransparentRenderer::renderDepthPeeling(const FrameSetup& setup, StageSink& timer) {
    timer.begin("peel");
    const GLuint pMin = m_peelMinProgram.id(), pShade = m_peelShadeProgram.id();
    setFragmentUniforms(pMin, setup);
    setFragmentUniforms(pShade, setup);
    int previous = 0;
    clearBuffer64(m_peelKeys[previous], 0);  // every fragment's key is > 0 (depth > 0)
    clearBuffer64(m_peelKeys[1 - previous], ~std::uint64_t(0));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kPeelCandidates, m_candidates.id());
    int layers = 0;
    while (m_maxPeelLayers == 0 || layers < m_maxPeelLayers) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kPeelPrevious, m_peelKeys[previous].id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kPeelCurrent, m_peelKeys[1 - previous].id());
        const GLuint zeroCount = 0;
        glNamedBufferSubData(m_candidates.id(), 0, sizeof(GLuint), &zeroCount);
        glUseProgram(pMin);
        m_geometry.draw(0, m_geometry.segmentCount());
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        GLuint candidates = 0;
        glGetNamedBufferSubData(m_candidates.id(), 0, sizeof(GLuint), &candidates);
        if (candidates == 0) break;
        glUseProgram(pShade);
        m_geometry.draw(0, m_geometry.segmentCount());
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        ++layers;
        previous = 1 - previous;
        clearBuffer64(m_peelKeys[1 - previous], ~std::uint64_t(0));
    }
    m_lastPeelLayers = layers;
    timer.setItems(std::uint64_t(layers));
    timer.end();
}

nlohmann::json TransparentRenderer::describe() const {
    nlohmann::json j = {{"technique", "rasterized"},
                        {"transparency", std::string(transparencyName(m_mode))},
                        {"cap_clipping", m_capClipping},
                        {"billboards", m_geometry.describeBillboards()},
                        {"billboard_shape", m_geometry.describeBillboardShape()},
                        {"ambient_occlusion", m_ao ? m_ao->describe() : nlohmann::json(false)},
                        {"aovs_from", m_gbuffer ? "G-buffer pass (first surface of the union of tubes)" : "none"}};
    if (m_mode == Transparency::KBuffer) j["k"] = m_k;
    if (m_mode != Transparency::ObjectOrder) j["synchronisation"] = m_synchronisation;
    if (m_mode != Transparency::DepthPeeling) j["sort"] = "GPU radix sort of segment distance keys";
    j["culling"] = m_culling ? m_culling->describe() : nlohmann::json(false);
    return j;
}

}  // namespace tc::gl
