#include "gl/line_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gl/bindings.h"
#include "gl/frame_uniforms.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"

namespace tc::gl {

namespace {

constexpr GLuint kBillboardGroupSize = 128;  // local_size_x of shaders/billboard_pass.comp

template <class T>
Buffer upload(const std::vector<T>& v) {
    return makeBuffer(v.size() * sizeof(T), v.data(), 0);
}

}  // namespace

std::size_t LineGeometry::uploadBytes(const StyledLines& lines) {
    auto bytes = [](const auto& v) { return v.size() * sizeof(v[0]); };
    return bytes(lines.positionRadius) + bytes(lines.color) + bytes(lines.polylineId) + bytes(lines.flags) +
           bytes(lines.segmentVertices);
}

LineGeometry LineGeometry::create(const StyledLines& lines, BillboardPath path, const RegionSetup& region,
                                  BillboardShape shape) {
    LineGeometry g;
    g.m_path = path;
    g.m_shape = shape;
    g.m_segmentCount = lines.segmentCount();
    g.m_maxRadius = region.maxRadiusOr(lines.maxRadius);
    g.m_bounds = region.boundsOr(lines.bounds);
    g.m_region = region.box;
    g.m_positionRadius = upload(lines.positionRadius);
    g.m_colors = upload(lines.color);
    g.m_polylineIds = upload(lines.polylineId);
    g.m_flags = upload(lines.flags);
    g.m_segmentVertices = upload(lines.segmentVertices);
    if (path == BillboardPath::Compute) {
        g.m_billboardCorners = makeBuffer(lines.segmentCount() * 2 * sizeof(glm::vec4));
        // kSegmentRecordSize vec4 per segment (shaders/segment_varyings.glsl).
        g.m_segmentRecords = makeBuffer(lines.segmentCount() * 7 * sizeof(glm::vec4));
        g.m_billboardProgram = compileProgram({{GL_COMPUTE_SHADER, "billboard_pass.comp"}}, g.billboardDefines());
    }
    g.m_emptyVao = VertexArray::create();
    if (path != BillboardPath::Geometry) {
        g.m_quads = QuadIndices::create();
        g.m_quads.attachTo(g.m_emptyVao);
    }
    return g;
}

void LineGeometry::bind() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kPositionRadius, m_positionRadius.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVertexColors, m_colors.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kPolylineIds, m_polylineIds.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSegmentVertices, m_segmentVertices.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVertexFlags, m_flags.id());
    if (m_billboardCorners)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kBillboardCorners, m_billboardCorners.id());
    if (m_segmentRecords) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSegmentRecords, m_segmentRecords.id());
    if (m_frameUniforms) bindFrameUniforms(m_frameUniforms);
}

const char* LineGeometry::describeBillboards() const {
    switch (m_path) {
        case BillboardPath::Compute:
            return "compute pre-pass, vertex pulling";
        case BillboardPath::Vertex:
            return "vertex shader, vertex pulling";
        case BillboardPath::Geometry:
            return "geometry shader";
    }
    return "?";
}

namespace {
// A GLSL float literal that round-trips the float (exponent form always has the '.' GLSL needs).
std::string glslFloat(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9e", double(v));
    return text;
}
}  // namespace

std::vector<std::string> haloDefines(const LineHalo& halo) {
    const glm::vec3& c = halo.color;
    return {"HALO", "HALO_WIDTH " + glslFloat(halo.geometry.width), "HALO_DEPTH " + glslFloat(halo.geometry.depth),
            "HALO_COLOR vec3(" + glslFloat(c.x) + ", " + glslFloat(c.y) + ", " + glslFloat(c.z) + ")"};
}

void LineGeometry::enableHalo(const LineHalo& halo) {
    m_haloDefines = gl::haloDefines(halo);
    // Halo fragments lie up to `depth` radii behind a tube's axis: keep them inside the depth range.
    m_maxRadius *= 1.0f + std::max(halo.geometry.width, halo.geometry.depth);
    if (m_path == BillboardPath::Compute) {
        std::vector<std::string> defines = m_haloDefines;
        for (const std::string& d : billboardDefines()) defines.push_back(d);
        m_billboardProgram = compileProgram({{GL_COMPUTE_SHADER, "billboard_pass.comp"}}, defines);
    }
}

float LineGeometry::farDepth(const FrameSetup& setup) const {
    // Beyond everything the data can reach. A 32-bit float depth buffer holding view depth / far
    // keeps ~1e-7 relative precision over the whole range.
    return glm::distance(setup.camera.eye, m_bounds.center()) + m_bounds.radius() + 2.0f * m_maxRadius + 1e-6f;
}

void LineGeometry::setFrame(const FrameSetup& setup, const LightingSpec& lighting) {
    const Camera& cam = setup.camera;
    const float aspect =
        float(fullWidthOf(setup.window, setup.width)) / float(fullHeightOf(setup.window, setup.height));
    const float far = farDepth(setup);
    FrameUniforms u = frameUniforms(setup, lighting);
    u.viewProj = projectionMatrix(cam, aspect, std::max(1e-4f * far, 1e-7f), far) * cam.worldToCamera();
    u.farDepth = far;
    u.capClipping = m_capClipping ? 1 : 0;
    setRegionUniforms(u, m_region);
    uploadFrameUniforms(m_frameUniforms, u);
}

Program LineGeometry::compileDrawProgram(const char* fragmentShader, std::vector<std::string> defines) const {
    defines.insert(defines.end(), m_haloDefines.begin(), m_haloDefines.end());
    if (!m_region.unbounded()) defines.push_back("REGION_CLIP");
    for (const std::string& d : billboardDefines()) defines.push_back(d);
    switch (m_path) {
        case BillboardPath::Compute:
            defines.push_back("BILLBOARDS_PRECOMPUTED");
            return compileProgram(
                {{GL_VERTEX_SHADER, "rounded_cone_gbuffer.vert"}, {GL_FRAGMENT_SHADER, fragmentShader}}, defines);
        case BillboardPath::Vertex:
            return compileProgram(
                {{GL_VERTEX_SHADER, "rounded_cone_gbuffer.vert"}, {GL_FRAGMENT_SHADER, fragmentShader}}, defines);
        case BillboardPath::Geometry:
            return compileProgram({{GL_VERTEX_SHADER, "rounded_cone_segment.vert"},
                                   {GL_GEOMETRY_SHADER, "rounded_cone_billboard.geom"},
                                   {GL_FRAGMENT_SHADER, fragmentShader}},
                                  defines);
    }
    return {};
}

void LineGeometry::computeBillboards(StageSink& timer) const {
    if (m_path != BillboardPath::Compute) return;
    timer.begin("billboards");
    buildBillboards(m_billboardProgram.id(), 0, m_segmentCount);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    timer.setItems(m_segmentCount);
    timer.end();
}

void LineGeometry::buildBillboards(GLuint program, std::size_t firstSlot, std::size_t count) const {
    glProgramUniform1ui(program, uniformLocation(program, "uSlotEnd"), GLuint(firstSlot + count));
    glUseProgram(program);
    bind();
    dispatchItems(program, "uFirstSlot", firstSlot, count, kBillboardGroupSize);
}

void LineGeometry::draw(std::size_t first, std::size_t count) const {
    glBindVertexArray(m_emptyVao.id());
    bind();
    if (m_path == BillboardPath::Geometry)
        glDrawArrays(GL_POINTS, GLint(first), GLsizei(count));
    else
        m_quads.draw(first, count);
}

}  // namespace tc::gl
