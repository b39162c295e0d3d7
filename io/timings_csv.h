#pragma once
// Per-frame, per-stage timings as CSV: `frame,stage,gpu_ms,cpu_ms,items`; a data-parallel render
// (`tubecast render --mpi`) writes every rank's rows, `frame,rank,stage,gpu_ms,cpu_ms,items`.
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace tc {

struct TimingRow {
    int frame = 0;
    std::string stage;
    double gpuMs = -1.0;  // negative = unknown (no timer query): written as an empty field
    double cpuMs = 0.0;
    std::uint64_t items = 0;  // what the stage processed (segments, fragments, ...)
    int rank = 0;             // the MPI rank that measured it (written only with the rank column)
};

// Owns an open CSV file. The header is written when the file is created, or when `append` is
// set and the file is new or empty. Each write() is flushed, so a killed run keeps the rows of
// its finished frames. Not an AtomicFile: the point is to keep partial results.
inline constexpr const char* kTimingsHeader = "frame,stage,gpu_ms,cpu_ms,items";
inline constexpr const char* kRankTimingsHeader = "frame,rank,stage,gpu_ms,cpu_ms,items";

class TimingsCsv {
public:
    // Throws OutputError "PATH: cannot write: <reason>". `rankColumn`: the data-parallel header
    // (appending to a file with the other header is refused: OutputError naming both).
    TimingsCsv(std::string path, bool append, bool rankColumn = false);

    // Writes the rows (one frame's, typically) and flushes. Times with 3 decimals, '.' as the
    // decimal separator regardless of locale. Throws OutputError on a write error.
    void write(const std::vector<TimingRow>& rows);

    const std::string& path() const { return m_path; }

private:
    std::string m_path;
    bool m_rankColumn = false;
    std::ofstream m_out;
};

}  // namespace tc
