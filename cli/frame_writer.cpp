#include "cli/frame_writer.h"

namespace tc::cli {

FrameWriter::FrameWriter(bool overlap, bool keepGoing, std::uint64_t items, Callbacks callbacks)
    : m_overlap(overlap),
      m_keepGoing(keepGoing),
      m_items(items),
      m_callbacks(std::move(callbacks)),
      m_lastDone(std::chrono::steady_clock::now()) {}

FrameWriter::~FrameWriter() {
    if (m_pending && m_pending->write.valid()) m_pending->write.wait();
}

FrameImages& FrameWriter::nextImages() {
    FrameImages& images = m_buffers[m_next];
    if (m_overlap) m_next ^= 1;
    return images;
}

void FrameWriter::report(Pending& p) {
    try {
        const Written w = p.write.get();
        const double frameMs = std::chrono::duration<double, std::milli>(w.end - p.job.start).count();
        const double intervalMs = std::chrono::duration<double, std::milli>(w.end - m_lastDone).count();
        m_lastDone = w.end;
        p.job.rows.push_back({p.job.frame, "write", -1.0, w.ms, p.job.outputs});
        p.job.rows.push_back({p.job.frame, "frame", -1.0, frameMs, m_items});
        p.job.rows.push_back({p.job.frame, "frame_interval", -1.0, intervalMs, m_items});
        if (m_callbacks.done) m_callbacks.done(p.job.frame, p.job.rows, frameMs);
    } catch (const std::exception& e) {
        if (!m_keepGoing) throw;
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - p.job.start).count();
        if (m_callbacks.failed) m_callbacks.failed(p.job.frame, seconds, e.what());
    }
}

void FrameWriter::flush() {
    if (!m_pending) return;
    Pending p = std::move(*m_pending);
    m_pending.reset();
    report(p);
}

void FrameWriter::submit(FrameJob job) {
    auto write = [fn = std::move(job.write)] {
        const auto start = std::chrono::steady_clock::now();
        fn();
        const auto end = std::chrono::steady_clock::now();
        return Written{std::chrono::duration<double, std::milli>(end - start).count(), end};
    };
    job.write = nullptr;
    flush();  // the previous frame, so frames are reported in order
    Pending p{std::move(job), {}};
    if (m_overlap) {
        p.write = std::async(std::launch::async, std::move(write));
        m_pending = std::move(p);
        return;
    }
    std::promise<Written> done;
    try {
        done.set_value(write());
    } catch (...) {
        done.set_exception(std::current_exception());
    }
    p.write = done.get_future();
    report(p);
}

}  // namespace tc::cli
