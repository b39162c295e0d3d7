#include "gl/sort_keys.h"

#include <algorithm>

#include "core/error.h"
#include "gl/bindings.h"
#include "gl/gl_api.h"
#include "gl/shader_library.h"

namespace tc::gl {
namespace {

constexpr GLuint kLocalSize = 64;  // local_size_x of shaders/segment_sort_keys.comp

void ensureSize(Buffer& buffer, std::size_t bytes) {
    if (buffer) {
        GLint64 size = 0;
        glGetNamedBufferParameteri64v(buffer.id(), GL_BUFFER_SIZE, &size);
        if (static_cast<std::size_t>(size) >= bytes) return;
    }
    buffer = makeBuffer(bytes);
}

}  // namespace

SegmentSortKeys SegmentSortKeys::create() {
    SegmentSortKeys pass;
    pass.m_program = compileProgram({{GL_COMPUTE_SHADER, "segment_sort_keys.comp"}});
    GLuint id = pass.m_program.id();
    pass.m_segmentCount = glGetUniformLocation(id, "segmentCount");
    pass.m_firstSegment = glGetUniformLocation(id, "firstSegment");
    pass.m_eye = glGetUniformLocation(id, "eye");
    pass.m_forward = glGetUniformLocation(id, "forward");
    pass.m_orthographic = glGetUniformLocation(id, "orthographic");
    pass.m_frustumTest = glGetUniformLocation(id, "frustumTest");
    pass.m_frustumPlanes = glGetUniformLocation(id, "frustumPlanes");
    pass.m_outside = makeBuffer(sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);
    return pass;
}

void SegmentSortKeys::compute(const Buffer& positionRadius, const Buffer& segmentVertices, std::size_t segments,
                              const glm::vec3& eye, bool orthographic, const glm::vec3& forward, Buffer& keysOut,
                              Buffer& segmentIdsOut, const ViewFrustum* frustum) {
    ensureSize(keysOut, segments * sizeof(GLuint));
    ensureSize(segmentIdsOut, segments * sizeof(GLuint));
    const GLuint zero = 0;
    glNamedBufferSubData(m_outside.id(), 0, sizeof zero, &zero);
    if (segments == 0) return;
    TC_CHECK_OP(segments, <=, std::size_t(0xFFFFFFFFu));

    GLuint id = m_program.id();
    glProgramUniform1ui(id, m_segmentCount, static_cast<GLuint>(segments));
    glProgramUniform3f(id, m_eye, eye.x, eye.y, eye.z);
    glProgramUniform3f(id, m_forward, forward.x, forward.y, forward.z);
    glProgramUniform1i(id, m_orthographic, orthographic ? 1 : 0);
    glProgramUniform1i(id, m_frustumTest, frustum ? 1 : 0);
    if (frustum) glProgramUniform4fv(id, m_frustumPlanes, 5, &frustum->planes[0].x);
    glUseProgram(id);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSortPositionRadius, positionRadius.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSortSegmentVertices, segmentVertices.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSortKeys, keysOut.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSortSegmentIds, segmentIdsOut.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kSortOutsideCount, m_outside.id());
    // 65535 is the minimum GL_MAX_COMPUTE_WORK_GROUP_COUNT; larger inputs take several dispatches.
    constexpr std::size_t kChunk = std::size_t(65535) * kLocalSize;
    for (std::size_t first = 0; first < segments; first += kChunk) {
        std::size_t n = std::min(kChunk, segments - first);
        glProgramUniform1ui(id, m_firstSegment, static_cast<GLuint>(first));
        glDispatchCompute(static_cast<GLuint>((n + kLocalSize - 1) / kLocalSize), 1, 1);
    }
    glUseProgram(0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

std::size_t SegmentSortKeys::outsideCount() const {
    GLuint outside = 0;
    glGetNamedBufferSubData(m_outside.id(), 0, sizeof outside, &outside);
    return outside;
}

}  // namespace tc::gl
