#pragma once
// The frame writer pipeline of `tubecast render`: a rendered frame's outputs (compositing over the
// background, sRGB / zlib / EXR encoding, temp file + rename) are written on a second thread while
// the next frame renders, so the writer's mostly serial work fills the cores the renderer leaves
// idle. At most one write is in flight, from the other of two reused FrameImages (no page faults
// or fresh zeroing per frame). Frames are reported (timings, progress, failures) in the order they
// were submitted, as their writes finish.
#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <optional>
#include <string>
#include <vector>

#include "core/frame_images.h"
#include "io/timings_csv.h"

namespace tc::cli {

// One rendered frame, ready to be written.
struct FrameJob {
    int frame = 0;
    std::size_t outputs = 0;                      // files the write produces (the "write" row's items)
    std::vector<TimingRow> rows;                  // the frame's render stages
    std::chrono::steady_clock::time_point start;  // when its render began
    std::function<void()> write;                  // writes every output of the frame; may throw
};

class FrameWriter {
public:
    struct Callbacks {
        // A frame whose outputs are complete, with its rows plus "write" (the write's time),
        // "frame" (latency: render start to outputs complete) and "frame_interval" (outputs complete
        // since the previous frame's: the throughput, which overlapping writes improve).
        std::function<void(int frame, const std::vector<TimingRow>& rows, double frameMs)> done;
        // A frame whose write failed, with --keep-going (without it the error propagates).
        std::function<void(int frame, double seconds, const std::string& error)> failed;
    };

    // overlap: write on a second thread while the next frame renders; else write in submit().
    // `items`: the "frame" and "frame_interval" rows' items (the dataset's segments).
    FrameWriter(bool overlap, bool keepGoing, std::uint64_t items, Callbacks callbacks);
    FrameWriter(const FrameWriter&) = delete;
    FrameWriter& operator=(const FrameWriter&) = delete;
    // Waits for a write still in flight (its outcome is dropped: this only happens on the way out
    // of an error).
    ~FrameWriter();

    // The images the next frame renders into: with overlap, two buffers alternate, so the one a
    // write reads is never the one being rendered into.
    FrameImages& nextImages();
    // Hands over the frame rendered into the images nextImages() returned last. Reports the frame
    // before it first, then writes this one (in the background with overlap).
    void submit(FrameJob job);
    // Waits for the write in flight and reports it.
    void flush();

private:
    struct Written {
        double ms;
        std::chrono::steady_clock::time_point end;
    };
    struct Pending {
        FrameJob job;
        std::future<Written> write;
    };
    void report(Pending& p);

    bool m_overlap, m_keepGoing;
    std::uint64_t m_items;
    Callbacks m_callbacks;
    FrameImages m_buffers[2];
    int m_next = 0;
    std::chrono::steady_clock::time_point m_lastDone;
    std::optional<Pending> m_pending;  // after the buffers: waited for before they go
};

}  // namespace tc::cli
