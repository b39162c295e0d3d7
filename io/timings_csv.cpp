#include "io/timings_csv.h"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>

#include "core/error.h"

namespace tc {

namespace {

void appendFixed3(std::string& out, double v) {
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 3);
    out.append(buf, r.ptr);
}

// RFC 4180 quoting, only when needed: stage names are identifiers in practice.
void appendField(std::string& out, const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) {
        out += s;
        return;
    }
    out += '"';
    for (char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    out += '"';
}

}  // namespace

TimingsCsv::TimingsCsv(std::string path, bool append, bool rankColumn)
    : m_path(std::move(path)), m_rankColumn(rankColumn) {
    const std::string header = rankColumn ? kRankTimingsHeader : kTimingsHeader;
    std::error_code ec;
    bool needHeader = !append || !std::filesystem::exists(m_path, ec) || std::filesystem::file_size(m_path, ec) == 0;
    if (!needHeader) {
        // --resume appends: a file of the other layout would get rows of a different width.
        std::ifstream existing(m_path);
        std::string first;
        std::getline(existing, first);
        if (!first.empty() && first.back() == '\r') first.pop_back();
        if (existing && first != header)
            throw OutputError(m_path + ": cannot append rows \"" + header + "\" to a file whose header is \"" + first +
                              "\" (render it again with or without --mpi as before, or use --overwrite)");
    }
    m_out.open(m_path, append ? std::ios::app : std::ios::trunc);
    if (!m_out) throw OutputError(m_path + ": cannot write: " + std::strerror(errno));
    if (needHeader) {
        m_out << header << "\n";
        m_out.flush();
        if (!m_out) throw OutputError(m_path + ": cannot write: " + std::strerror(errno));
    }
}

void TimingsCsv::write(const std::vector<TimingRow>& rows) {
    std::string text;
    for (const TimingRow& row : rows) {
        text += std::to_string(row.frame);
        text += ',';
        if (m_rankColumn) {
            text += std::to_string(row.rank);
            text += ',';
        }
        appendField(text, row.stage);
        text += ',';
        if (row.gpuMs >= 0.0) appendFixed3(text, row.gpuMs);
        text += ',';
        appendFixed3(text, row.cpuMs);
        text += ',';
        text += std::to_string(row.items);
        text += '\n';
    }
    m_out << text;
    m_out.flush();
    if (!m_out) throw OutputError(m_path + ": cannot write: " + std::strerror(errno));
}

}  // namespace tc
