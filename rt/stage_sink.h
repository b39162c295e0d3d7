#pragma once
// Where the ray tracer reports its per-frame stages. gl::StageTimer (gl/gpu_timer.h) needs a GL
// context for its timestamp queries, and rt/ must run without one, so the technique talks to this
// interface: the frame loop adapts it to its StageTimer (cli/technique_factory.cpp), tests and
// benchmarks use CpuStageTimer. Moving gl::Technique and StageTimer into core/ would have touched
// every GL technique and the shared frame loop at once while other milestones edit them.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace tc::rt {

class StageSink {
public:
    virtual ~StageSink() = default;
    virtual void begin(std::string stage) = 0;
    virtual void end() = 0;
    virtual void setItems(std::uint64_t items) = 0;  // of the stage begun last
};

// Wall-clock stages of one or more frames, in begin() order.
class CpuStageTimer final : public StageSink {
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

}  // namespace tc::rt
