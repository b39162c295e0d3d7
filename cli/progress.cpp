#include "cli/progress.h"

#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace tc::cli {

std::string formatSeconds(double s) {
    std::ostringstream out;
    if (s < 60)
        out << std::fixed << std::setprecision(1) << s << " s";
    else if (s < 3600)
        out << int(s / 60) << " min " << int(std::fmod(s, 60.0)) << " s";
    else
        out << int(s / 3600) << " h " << int(std::fmod(s, 3600.0) / 60) << " min";
    return out.str();
}

Progress::Progress(std::size_t total, bool quiet, bool json, std::ostream& err, std::ostream& out, bool tty)
    : m_total(total),
      m_quiet(quiet),
      m_json(json),
      m_err(err),
      m_out(out),
      m_tty(tty),
      m_start(std::chrono::steady_clock::now()) {}

void Progress::frameSkipped(int frame, const std::string& why) {
    ++m_done;
    if (m_json)
        emit({{"event", "skipped"}, {"frame", frame}, {"reason", why}});
    else if (!m_quiet)
        m_err << (m_tty ? "\r\033[K" : "") << "tubecast: frame " << frame << " skipped: " << why << "\n";
}

void Progress::event(nlohmann::json e) {
    if (m_json) emit(e);
}

void Progress::report(int frame, double seconds, const std::string& error) {
    ++m_done;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    const double fps = wall > 0 ? double(m_done) / wall : 0.0;
    const double eta = fps > 0 ? double(m_total - m_done) / fps : 0.0;
    if (m_json) {
        nlohmann::json e = {{"event", error.empty() ? "frame" : "failed"},
                            {"frame", frame},
                            {"done", m_done},
                            {"total", m_total},
                            {"seconds", seconds},
                            {"frames_per_s", fps},
                            {"eta_s", eta}};
        if (!error.empty()) e["error"] = error;
        emit(e);
        return;
    }
    if (!error.empty()) {
        // Failures are never silenced: they are the frames to re-run.
        m_err << (m_tty ? "\r\033[K" : "") << "error: frame " << frame << ": " << error << "\n";
        return;
    }
    if (m_quiet) return;
    std::ostringstream line;
    line << "frame " << m_done << "/" << m_total << " (#" << frame << ") " << std::fixed << std::setprecision(2)
         << seconds << " s, " << fps << " frames/s, ETA " << formatSeconds(eta);
    if (m_tty)
        m_err << "\r\033[K" << line.str() << (m_done == m_total ? "\n" : "") << std::flush;
    else
        m_err << "tubecast: " << line.str() << "\n";
}

void Progress::emit(const nlohmann::json& e) {
    m_out << e.dump() << "\n" << std::flush;
}

}  // namespace tc::cli
