#include "gl/hierarchical_culling.h"

#include <algorithm>

#include "core/error.h"
#include "core/technique_registry.h"
#include "gl/bindings.h"
#include "gl/context.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/segment_order.h"
#include "gl/shader_library.h"

namespace tc::gl {

namespace {

constexpr std::size_t kMaxLevels = 32;   // TC_CULL_MAX_LEVELS
constexpr GLuint kPyramidGroupSize = 8;  // local size of cull_pyramid.comp

const char* targetDefine(HierarchicalCulling::Target t) {
    return t == HierarchicalCulling::Target::MaxDepth ? "CULL_MAX_DEPTH" : "CULL_MIN_OPACITY";
}

HierarchicalCulling::FragmentTest g_fragmentTest = HierarchicalCulling::FragmentTest::Auto;

}  // namespace

void HierarchicalCulling::setFragmentTest(FragmentTest mode) {
    g_fragmentTest = mode;
}

HierarchicalCulling HierarchicalCulling::create(Target target, const CullingSpec& spec, const LineGeometry& geometry) {
    HierarchicalCulling c;
    c.m_target = target;
    c.m_slices = spec.slices;
    c.m_threshold = spec.opacityThreshold;
    if (target == Target::MaxDepth)
        c.m_fragmentTest = g_fragmentTest == FragmentTest::Auto ? !isSoftwareRasterizer(currentContextInfo().renderer)
                                                                : g_fragmentTest == FragmentTest::On;
    const std::string define = targetDefine(target);
    c.m_fromSource = compileProgram({{GL_COMPUTE_SHADER, "cull_pyramid.comp"}}, {define, "FROM_SOURCE"});
    c.m_fromLevel = compileProgram({{GL_COMPUTE_SHADER, "cull_pyramid.comp"}}, {define});
    if (geometry.billboardPath() == BillboardPath::Compute) {
        std::vector<std::string> defines = c.drawDefines();
        for (const std::string& d : geometry.billboardDefines()) defines.push_back(d);
        defines.insert(defines.end(), geometry.haloDefines().begin(), geometry.haloDefines().end());
        c.m_billboards = compileProgram({{GL_COMPUTE_SHADER, "billboard_pass.comp"}}, defines);
    }
    if (target == Target::MinOpacity) {
        c.m_mark = compileProgram({{GL_VERTEX_SHADER, "fullscreen.vert"}, {GL_FRAGMENT_SHADER, "cull_mark.frag"}},
                                  {"CULLING", define});
        c.m_emptyVao = VertexArray::create();
    }
    c.m_counter = makeBuffer(sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);
    return c;
}

std::vector<std::string> HierarchicalCulling::drawDefines() const {
    std::vector<std::string> defines{"DRAW_ORDER", "CULLING", targetDefine(m_target)};
    if (m_fragmentTest) defines.push_back("CULL_FRAGMENT_TEST");
    return defines;
}

void HierarchicalCulling::resize(int width, int height) {
    if (width == m_width && height == m_height) return;
    m_width = width;
    m_height = height;
    m_levelSizes.clear();
    m_levelOffsets.clear();
    glm::ivec2 size{width, height};
    GLint total = 0;
    do {
        size = glm::max(size / 2, glm::ivec2(1));
        m_levelSizes.push_back(size);
        m_levelOffsets.push_back(total);
        total += size.x * size.y;
    } while (size.x > 1 || size.y > 1);
    TC_CHECK(m_levelSizes.size() <= kMaxLevels);
    m_pyramid = makeBuffer(std::size_t(total) * sizeof(float));
}

void HierarchicalCulling::reset() {
    // Nothing hidden yet: every depth in front of +inf, no opacity blended.
    const float nothing = m_target == Target::MaxDepth ? 3.0e38f : 0.0f;
    glClearNamedBufferData(m_pyramid.id(), GL_R32F, GL_RED, GL_FLOAT, &nothing);
    const GLuint zero = 0;
    glNamedBufferSubData(m_counter.id(), 0, sizeof(GLuint), &zero);
}

void HierarchicalCulling::build(const Texture& source, int width, int height, float farDepth) {
    resize(width, height);
    rebuild(source, farDepth);
}

std::vector<float> HierarchicalCulling::readLevel(int level, glm::ivec2& size) const {
    size = m_levelSizes.at(std::size_t(level));
    std::vector<float> v(std::size_t(size.x) * std::size_t(size.y));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(m_pyramid.id(), GLintptr(m_levelOffsets[std::size_t(level)]) * GLintptr(sizeof(float)),
                            GLsizeiptr(v.size() * sizeof(float)), v.data());
    return v;
}

void HierarchicalCulling::rebuild(const Texture& source, float farDepth) {
    // Framebuffer writes of the last slice are visible to texture fetches issued after them.
    auto groups = [](int n) { return GLuint((n + int(kPyramidGroupSize) - 1) / int(kPyramidGroupSize)); };
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kCullPyramid, m_pyramid.id());
    const GLuint s = m_fromSource.id();
    glProgramUniform1f(s, uniformLocation(s, "uFarDepth"), farDepth);
    glProgramUniform1i(s, uniformLocation(s, "uLevelOffset"), m_levelOffsets[0]);
    glProgramUniform2i(s, uniformLocation(s, "uLevelSize"), m_levelSizes[0].x, m_levelSizes[0].y);
    glUseProgram(s);
    glBindTextureUnit(binding::kCullSource, source.id());
    glDispatchCompute(groups(m_levelSizes[0].x), groups(m_levelSizes[0].y), 1);
    const GLuint l = m_fromLevel.id();
    glUseProgram(l);
    for (std::size_t i = 1; i < m_levelSizes.size(); ++i) {
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glProgramUniform1i(l, uniformLocation(l, "uSourceOffset"), m_levelOffsets[i - 1]);
        glProgramUniform2i(l, uniformLocation(l, "uSourceSize"), m_levelSizes[i - 1].x, m_levelSizes[i - 1].y);
        glProgramUniform1i(l, uniformLocation(l, "uLevelOffset"), m_levelOffsets[i]);
        glProgramUniform2i(l, uniformLocation(l, "uLevelSize"), m_levelSizes[i].x, m_levelSizes[i].y);
        glDispatchCompute(groups(m_levelSizes[i].x), groups(m_levelSizes[i].y), 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void HierarchicalCulling::setUniforms(GLuint p) const {
    const GLsizei n = GLsizei(m_levelSizes.size());
    glProgramUniform1i(p, uniformLocation(p, "uCullLevels"), n);
    glProgramUniform2iv(p, uniformLocation(p, "uCullLevelSize"), n, &m_levelSizes[0].x);
    glProgramUniform1iv(p, uniformLocation(p, "uCullLevelOffset"), n, m_levelOffsets.data());
    glProgramUniform1f(p, uniformLocation(p, "uCullThreshold"), m_threshold);
}

void HierarchicalCulling::drawSliced(const LineGeometry& geometry, const SegmentOrder& order, GLuint program,
                                     const Texture& source, const FrameSetup& setup) {
    resize(setup.width, setup.height);
    reset();
    setUniforms(program);
    const GLuint billboards = m_billboards.id();
    if (billboards) setUniforms(billboards);
    if (m_mark) {
        setUniforms(m_mark.id());
        // Nothing hidden yet: depth 1 everywhere; the billboards lie at depth 0.5 (NDC z = 0).
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_TRUE);
        const float far = 1.0f;
        glClearBufferfv(GL_DEPTH, 0, &far);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_LESS);
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kCullPyramid, m_pyramid.id());
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, binding::kCulledSegments, m_counter.id());
    // The slices are cut from the segments in view (the order's prefix, gl/segment_order.h); the
    // rest cannot rasterize in the view the order was sorted for, and is one more slice when the
    // order is reused for another view (opaque culling re-sorts only after large changes).
    const std::size_t n = geometry.segmentCount();
    const std::size_t inView = order.inViewCount();
    const bool tail = inView < n && !order.sortedForView(setup);
    for (int s = 0; s < m_slices + (tail ? 1 : 0); ++s) {
        const std::size_t first = s < m_slices ? inView * std::size_t(s) / std::size_t(m_slices) : inView;
        const std::size_t end = s < m_slices ? inView * std::size_t(s + 1) / std::size_t(m_slices) : n;
        if (end == first) continue;
        if (first > 0) rebuild(source, geometry.farDepth(setup));
        order.bind();
        if (billboards) {
            geometry.buildBillboards(billboards, first, end - first);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
        // Marked after the billboard pass and its barrier, which on llvmpipe wait for the draws
        // still pending: the marking pass then rasterizes together with the slice's draw instead
        // of on its own (3-7 % less wall time of the culled k-buffer, docs/performance.md). The
        // billboard pass only reads the pyramid, not the marks.
        if (first > 0 && m_mark) markHidden();
        glUseProgram(program);
        order.bind();
        geometry.draw(first, end - first);
    }
    if (m_mark) glDisable(GL_DEPTH_TEST);
}

void HierarchicalCulling::markHidden() const {
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_ALWAYS);
    glUseProgram(m_mark.id());
    glBindVertexArray(m_emptyVao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);  // colour writes are on outside such passes
}

std::uint64_t HierarchicalCulling::readCulled(StageSink& timer) const {
    timer.begin("culling");
    glMemoryBarrier(GL_ATOMIC_COUNTER_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint culled = 0;
    glGetNamedBufferSubData(m_counter.id(), 0, sizeof(GLuint), &culled);
    timer.setItems(culled);
    timer.end();
    return culled;
}

nlohmann::json HierarchicalCulling::describe() const {
    return {
        {"slices", m_slices},
        {"pyramid", m_target == Target::MaxDepth ? "max view depth" : "min accumulated opacity"},
        {"opacity_threshold", m_threshold},
        {"billboard_test", m_billboards ? "compute pre-pass, per slice" : "where the billboard is built"},
        {"frustum", "segments outside the view sorted last, not drawn (timings stage \"frustum\")"},
        {"fragment_test", m_target == Target::MinOpacity ? "depth test before the shader (pixels marked per slice)"
                          : m_fragmentTest               ? "in the shader, before the ray casting"
                                           : "none (software rasterizer: a discard does not skip the shader's work)"}};
}

}  // namespace tc::gl
