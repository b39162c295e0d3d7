#pragma once
// Per-frame stage timing: GPU time from GL timestamp queries, CPU time from std::chrono. The
// frame loop's StageSink (core/stage_sink.h) when a GL context exists.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "core/stage_sink.h"
#include "gl/objects.h"

namespace tc::gl {

// Times a frame's stages in order:
//     timer.begin("kbuffer"); ...; timer.setItems(n); timer.end();   ... one per stage
//     std::vector<StageTime> times = timer.collect();
// Stages do not nest. Needs a current context; reuses its timestamp queries across frames. The
// GPU time is the time between the two timestamps reaching the GPU, so it includes bubbles and
// is only meaningful when stages are submitted back to back (the frame loop does that).
class StageTimer final : public StageRecorder {
public:
    StageTimer() = default;

    void begin(std::string stage) override;  // glQueryCounter(GL_TIMESTAMP); starts the wall clock
    void end() override;                     // closes the stage begun last
    // Sets `items` of the stage begun last (open, or just ended).
    void setItems(std::uint64_t items) override;

    // Waits for the GPU to reach every timestamp, returns the frame's stages in begin() order and
    // starts a new frame. Throws tc::Error(Internal) if a stage is still open.
    std::vector<StageTime> collect() override;

private:
    struct Pending {
        StageTime time;
        Query begin, end;
        std::chrono::steady_clock::time_point cpuBegin;
    };
    Query takeQuery();

    std::vector<Pending> m_stages;
    std::vector<Query> m_free;  // queries of earlier frames, reused
    bool m_open = false;
};

}  // namespace tc::gl
