#include "gl/gpu_timer.h"

#include "core/error.h"

namespace tc::gl {

Query StageTimer::takeQuery() {
    if (m_free.empty()) return Query::create(GL_TIMESTAMP);
    Query query = std::move(m_free.back());
    m_free.pop_back();
    return query;
}

void StageTimer::begin(std::string stage) {
    if (m_open)
        throw Error(ExitCode::Internal,
                    "StageTimer::begin(\"" + stage + "\"): stage \"" + m_stages.back().time.stage + "\" is still open");
    Pending pending;
    pending.time.stage = std::move(stage);
    pending.begin = takeQuery();
    pending.end = takeQuery();
    glQueryCounter(pending.begin.id(), GL_TIMESTAMP);
    pending.cpuBegin = std::chrono::steady_clock::now();
    m_stages.push_back(std::move(pending));
    m_open = true;
}

void StageTimer::end() {
    TC_CHECK(m_open);
    Pending& pending = m_stages.back();
    glQueryCounter(pending.end.id(), GL_TIMESTAMP);
    pending.time.cpuMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - pending.cpuBegin).count();
    m_open = false;
}

void StageTimer::setItems(std::uint64_t items) {
    TC_CHECK(!m_stages.empty());
    m_stages.back().time.items = items;
}

std::vector<StageTime> StageTimer::collect() {
    if (m_open)
        throw Error(ExitCode::Internal,
                    "StageTimer::collect(): stage \"" + m_stages.back().time.stage + "\" is still open");
    std::vector<StageTime> times;
    times.reserve(m_stages.size());
    for (Pending& pending : m_stages) {
        // GL_QUERY_RESULT blocks until the GPU has written the timestamp.
        GLuint64 begin = 0, end = 0;
        glGetQueryObjectui64v(pending.begin.id(), GL_QUERY_RESULT, &begin);
        glGetQueryObjectui64v(pending.end.id(), GL_QUERY_RESULT, &end);
        pending.time.gpuMs = end > begin ? static_cast<double>(end - begin) * 1e-6 : 0.0;
        times.push_back(std::move(pending.time));
        m_free.push_back(std::move(pending.begin));
        m_free.push_back(std::move(pending.end));
    }
    m_stages.clear();
    return times;
}

}  // namespace tc::gl
