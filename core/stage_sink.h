#pragma once
// Where a technique reports the stages of a frame (timings.csv rows). The interface is GL-free so
// that the CPU ray tracer (rt/) and the GL techniques (gl/) report the same way: the frame loop
// passes gl::StageTimer (gl/gpu_timer.h: GPU timestamps as well as wall time) when a GL context
// exists; tests, benchmarks and GL-less runs pass CpuStageTimer (wall time only).
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace tc {

class StageSink {
public:
    virtual ~StageSink() = default;
    virtual void begin(std::string stage) = 0;
    virtual void end() = 0;
    virtual void setItems(std::uint64_t items) = 0;  // of the stage begun last
};

// One timed stage of a frame (a timings.csv row).
struct StageTime {
    std::string stage;
    double gpuMs = -1;        // GPU time between the stage's timestamps; -1 = not measured
    double cpuMs = 0;         // wall time between begin() and end() on the calling thread
    std::uint64_t items = 0;  // what the stage processed (segments, fragments, ...); 0 if unset
};

// A sink that keeps what it is told: the frame loop reads each frame's stages with collect().
class StageRecorder : public StageSink {
public:
    // The stages since the last collect(), in begin() order; starts a new frame.
    virtual std::vector<StageTime> collect() = 0;
};

// Wall-clock stages of one or more frames, in begin() order.
class CpuStageTimer final : public StageRecorder {
public:
    struct Stage {
        std::string stage;
        double cpuMs = 0;
        std::uint64_t items = 0;
    };

    void begin(std::string stage) override {
        m_stages.push_back({std::move(stage), 0.0, 0});
        m_start = std::chrono::steady_clock::now();
    }
    void end() override {
        m_stages.back().cpuMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m_start).count();
    }
    void setItems(std::uint64_t items) override { m_stages.back().items = items; }
    std::vector<StageTime> collect() override {
        std::vector<StageTime> out;
        for (const Stage& s : m_stages) out.push_back({s.stage, -1.0, s.cpuMs, s.items});
        m_stages.clear();
        return out;
    }
    // Every stage since construction or the last collect().
    const std::vector<Stage>& stages() const { return m_stages; }
    double totalMs() const {
        double t = 0;
        for (const auto& s : m_stages) t += s.cpuMs;
        return t;
    }

private:
    std::vector<Stage> m_stages;
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace tc
