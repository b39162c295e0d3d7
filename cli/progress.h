#pragma once
// Progress of `tubecast render`: a line rewritten in place on a terminal, plain log lines
// otherwise (both on stderr, silenced by -q), or JSON lines on stdout with --log-format json (one
// object per event, for workflow tools; not silenced by -q since they were asked for). frames/s
// and the ETA use the wall clock since the first frame started, so they include writing and
// waiting.
#include <chrono>
#include <cstddef>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

namespace tc::cli {

// "12.3 s", "4 min 5 s", "2 h 3 min".
std::string formatSeconds(double s);

class Progress {
public:
    // `err` / `out`: where human lines and JSON events go (std::cerr / std::cout; tests pass
    // string streams). `tty`: rewrite one line in place.
    Progress(std::size_t total, bool quiet, bool json, std::ostream& err, std::ostream& out, bool tty);

    void frameDone(int frame, double seconds) { report(frame, seconds, ""); }
    void frameFailed(int frame, double seconds, const std::string& message) { report(frame, seconds, message); }
    void frameSkipped(int frame, const std::string& why);
    // A JSON event (start, done); nothing in human mode.
    void event(nlohmann::json e);

private:
    void report(int frame, double seconds, const std::string& error);
    void emit(const nlohmann::json& e);

    std::size_t m_total, m_done = 0;
    bool m_quiet, m_json;
    std::ostream& m_err;
    std::ostream& m_out;
    bool m_tty;
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace tc::cli
