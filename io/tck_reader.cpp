// MRtrix .tck tracks and .tsf track scalars
// (https://mrtrix.readthedocs.io/en/latest/getting_started/image_data.html#tracks-file-format-tck).
// Both are a text header ("mrtrix tracks" / "mrtrix track scalars", "key: value" lines, "END")
// followed, at the offset given by "file: . OFFSET", by raw floats: NaN ends a track, Inf ends
// the file.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>

#include "core/error.h"
#include "io/line_formats.h"

namespace fs = std::filesystem;

namespace tc {

namespace {

// Header lines longer than this are not MRtrix headers (its command history lines are the
// longest, a few KiB); the limit only bounds what a broken file makes us scan.
constexpr std::size_t kMaxHeaderBytes = std::size_t(16) << 20;

struct MrtrixHeader {
    std::uint64_t dataOffset = 0;
    std::size_t elementBytes = 4;
    bool bigEndian = false;
    bool hasCount = false;
    std::uint64_t count = 0;
    std::size_t countLine = 0;
};

std::string trim(std::string_view s) {
    const char* ws = " \t\r";
    std::size_t b = s.find_first_not_of(ws);
    if (b == std::string_view::npos) return {};
    std::size_t e = s.find_last_not_of(ws);
    return std::string(s.substr(b, e - b + 1));
}

std::string lowerCase(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

// Parses the header of a .tck (`magic` "mrtrix tracks") or .tsf ("mrtrix track scalars") the
// way MRtrix reads it (core/file/key_value.cpp, KeyValue::Reader::next, and
// src/dwi/tractography/file_base.cpp, __ReaderBase__::open): text from '#' to the end of a line is
// a comment, keys are case-insensitive, a repeated `file` or `datatype` takes the last value, and
// `count` is advisory (MRtrix's writer fills it in when it closes the file; see checkCount). A
// line without a colon continues the value of the field before it, as MATLAB's
// write_mrtrix_tracks.m writes multi-line values and nibabel's tck.py reads them back; MRtrix
// skips such lines, and so do the fields used here (a continuation before the first field is an
// error, as in nibabel).
MrtrixHeader parseHeader(const ByteSource& source, const std::vector<std::uint8_t>& bytes, const char* magic) {
    MrtrixHeader h;
    const std::size_t limit = std::min(bytes.size(), kMaxHeaderBytes);
    std::string_view text(reinterpret_cast<const char*>(bytes.data()), limit);
    std::size_t pos = 0, line = 0;
    bool haveFile = false, haveType = false, ended = false, haveField = false;
    while (pos < text.size()) {
        std::size_t nl = text.find('\n', pos);
        if (nl == std::string_view::npos) break;  // a header line must end with a newline
        std::string_view raw = text.substr(pos, nl - pos);
        pos = nl + 1;
        ++line;
        if (line == 1) {
            if (trim(raw) != magic)
                source.failAtLine(1, std::string("not an MRtrix file (first line is not \"") + magic + "\")");
            continue;
        }
        std::string content = trim(raw.substr(0, raw.find('#')));
        if (content == "END") {
            ended = true;
            break;
        }
        if (content.empty()) continue;
        std::size_t colon = content.find(':');
        if (colon == std::string::npos) {
            if (!haveField)
                source.failAtLine(line,
                                  "expected \"key: value\" (a line without a colon continues the field "
                                  "before it, and there is none)");
            continue;
        }
        haveField = true;
        std::string key = lowerCase(trim(std::string_view(content).substr(0, colon)));
        std::string value = trim(std::string_view(content).substr(colon + 1));
        if (key == "datatype") {
            static const std::map<std::string, std::pair<std::size_t, bool>> types = {{"float32le", {4, false}},
                                                                                      {"float32be", {4, true}},
                                                                                      {"float64le", {8, false}},
                                                                                      {"float64be", {8, true}}};
            auto it = types.find(lowerCase(value));
            if (it == types.end())
                source.failAtLine(
                    line, "unsupported datatype \"" + value + "\" (Float32LE, Float32BE, Float64LE, Float64BE)");
            h.elementBytes = it->second.first;
            h.bigEndian = it->second.second;
            haveType = true;
        } else if (key == "file") {
            std::size_t space = value.find_first_of(" \t");
            std::string name = value.substr(0, space);
            if (name != ".")
                source.failAtLine(
                    line, "data in a separate file (\"" + name + "\") is not supported, only \"file: . OFFSET\"");
            std::string number = space == std::string::npos ? "" : trim(std::string_view(value).substr(space));
            auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), h.dataOffset);
            if (number.empty() || ec != std::errc() || end != number.data() + number.size())
                source.failAtLine(line, "expected \"file: . OFFSET\", got \"file: " + value + "\"");
            haveFile = true;
        } else if (key == "count") {
            std::uint64_t count = 0;
            auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), count);
            h.hasCount = ec == std::errc() && end == value.data() + value.size();
            h.count = count;
            h.countLine = line;
            if (!h.hasCount)
                source.warnAtLine(line, "count: expected a non-negative integer, got \"" + value + "\"; ignored");
        }
        // Other keys (timestamp, step_size, command_history, ...) are not needed to read the data.
    }
    if (line == 0) source.failAtLine(1, std::string("not an MRtrix file (no \"") + magic + "\" line)");
    if (!ended) source.failAtLine(line + 1, "header has no END line (truncated?)");
    if (!haveType) source.fail("header has no datatype");
    if (!haveFile) source.fail("header has no \"file: . OFFSET\" line");
    if (h.dataOffset < pos || h.dataOffset > bytes.size())
        source.failAt(h.dataOffset, "data offset " + std::to_string(h.dataOffset) +
                                        " is not between the end of the header (" + std::to_string(pos) +
                                        ") and the end of the file (" + std::to_string(bytes.size()) + ")");
    return h;
}

// Element i of the data section as float, whatever its stored type and byte order.
class Elements {
public:
    Elements(const std::vector<std::uint8_t>& bytes, const MrtrixHeader& h)
        : m_data(bytes.data() + h.dataOffset), m_count((bytes.size() - h.dataOffset) / h.elementBytes), m_h(h) {}
    std::size_t size() const { return m_count; }
    float operator[](std::size_t i) const {
        const std::uint8_t* p = m_data + i * m_h.elementBytes;
        if (m_h.elementBytes == 4) {
            std::uint32_t u = loadLittle<std::uint32_t>(p);
            if (m_h.bigEndian) u = byteSwap(u);
            float f;
            std::memcpy(&f, &u, 4);
            return f;
        }
        std::uint64_t u = loadLittle<std::uint64_t>(p);
        if (m_h.bigEndian) u = byteSwap(u);
        double d;
        std::memcpy(&d, &u, 8);
        return float(d);
    }
    std::uint64_t offsetOf(std::size_t i) const { return m_h.dataOffset + i * m_h.elementBytes; }

private:
    const std::uint8_t* m_data;
    std::size_t m_count;
    const MrtrixHeader& m_h;
};

// `count` is advisory: MRtrix writes it when the file is closed (a writer that stopped early
// leaves a stale one) and reads the data up to its end marker whatever the header says (Reader in
// src/dwi/tractography/file.h). A count that disagrees with the data is a warning.
void checkCount(const ByteSource& source, const MrtrixHeader& h, std::uint64_t tracks) {
    if (h.hasCount && h.count != tracks)
        source.warnAtLine(h.countLine, "count: " + std::to_string(h.count) + " tracks declared, the data holds " +
                                           std::to_string(tracks) + "; read " + std::to_string(tracks));
}

}  // namespace

LineSet readTck(const ByteSource& source) {
    const std::vector<std::uint8_t> bytes = source.readRest(0, "the file");
    const MrtrixHeader h = parseHeader(source, bytes, "mrtrix tracks");
    const Elements e(bytes, h);

    LineSet lines;
    // Bounded by the file size (one vertex per 3 elements), so the reserve cannot be a bomb.
    lines.positions.reserve(e.size() / 3);
    bool terminated = false;
    std::size_t i = 0;
    for (; i + 3 <= e.size(); i += 3) {
        const float x = e[i], y = e[i + 1], z = e[i + 2];
        if (std::isnan(x) && std::isnan(y) && std::isnan(z)) {
            lines.offsets.push_back(std::uint32_t(lines.positions.size()));
            continue;
        }
        if (std::isinf(x) && std::isinf(y) && std::isinf(z)) {
            terminated = true;
            break;
        }
        // A triplet with only some components NaN/Inf is a broken vertex, kept for cleanLineSet
        // to drop and count.
        if (lines.positions.size() == std::numeric_limits<std::uint32_t>::max())
            source.failAt(e.offsetOf(i), "more than 2^32 - 1 vertices are not supported");
        lines.positions.emplace_back(x, y, z);
    }
    if (!terminated) {
        // MRtrix's Reader also stops at the end of the data (and drops a track it was reading);
        // nibabel requires the Inf triplet. Read to the end when the data ends between tracks,
        // with a warning; data cut inside a triplet or a track is truncated.
        const std::uint64_t end = e.offsetOf(i);
        if (end != bytes.size())
            source.failAt(end, "truncated: the data ends without the Inf end-of-file triplet, inside a triplet (" +
                                   std::to_string(bytes.size() - end) + " bytes left)");
        if (lines.positions.size() != lines.offsets.back())
            source.failAt(end, "truncated: the data ends without the Inf end-of-file triplet, inside track " +
                                   std::to_string(lines.polylineCount()) + " (after " +
                                   std::to_string(lines.positions.size() - lines.offsets.back()) + " of its vertices)");
        source.warnAt(end, "the data ends without the Inf end-of-file triplet; read to the end (" +
                               std::to_string(lines.polylineCount()) + " tracks)");
    }
    // MRtrix always ends the last track with a NaN triplet; a file without one still has it.
    if (lines.positions.size() != lines.offsets.back()) lines.offsets.push_back(std::uint32_t(lines.positions.size()));
    checkCount(source, h, lines.polylineCount());
    return lines;
}

std::vector<float> readTsf(const ByteSource& source, const LineSet& tracks) {
    const std::vector<std::uint8_t> bytes = source.readRest(0, "the file");
    const MrtrixHeader h = parseHeader(source, bytes, "mrtrix track scalars");
    const Elements e(bytes, h);

    std::vector<float> values;
    values.reserve(std::min<std::size_t>(e.size(), tracks.vertexCount()));  // bounded by the file
    std::size_t track = 0, trackStart = 0, i = 0;
    bool terminated = false;
    auto endTrack = [&](std::size_t at) {
        const std::size_t n = values.size() - trackStart;
        if (track >= tracks.polylineCount())
            source.failAt(e.offsetOf(at),
                          "more tracks than the " + std::to_string(tracks.polylineCount()) + " of the tracks file");
        const std::size_t expected = tracks.offsets[track + 1] - tracks.offsets[track];
        if (n != expected)
            source.failAt(e.offsetOf(at), "track " + std::to_string(track) + " has " + std::to_string(n) +
                                              " values, the tracks file has " + std::to_string(expected) + " vertices");
        ++track;
        trackStart = values.size();
    };
    for (; i < e.size(); ++i) {
        const float v = e[i];
        if (std::isnan(v)) {
            endTrack(i);
        } else if (std::isinf(v)) {
            terminated = true;
            break;
        } else {
            values.push_back(v);
        }
    }
    if (!terminated) source.failAt(e.offsetOf(i), "truncated: the data ends without the Inf end-of-file value");
    if (values.size() != trackStart) endTrack(i);
    if (track != tracks.polylineCount())
        source.failAt(e.offsetOf(i), "holds " + std::to_string(track) + " tracks, the tracks file " +
                                         std::to_string(tracks.polylineCount()));
    checkCount(source, h, track);
    return values;
}

std::vector<std::pair<std::string, std::string>> findTsfFiles(const std::string& tckPath) {
    const fs::path tck(tckPath);
    const fs::path dir = tck.parent_path().empty() ? fs::path(".") : tck.parent_path();
    const std::string stem = tck.stem().string();
    std::vector<std::string> tckStems, tsfStems;
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
        const std::string ext = extensionLower(entry.path().string());
        if (ext == ".tck") tckStems.push_back(entry.path().stem().string());
        if (ext == ".tsf" && entry.is_regular_file(ec)) tsfStems.push_back(entry.path().filename().string());
    }
    // `s` (a .tsf stem) belongs to a .tck stem `t` as "t", "t_NAME", "t-NAME" or "t.NAME".
    auto suffixOf = [](const std::string& s, const std::string& t) -> std::optional<std::string> {
        if (s == t) return std::string("tsf");
        if (s.size() > t.size() + 1 && s.compare(0, t.size(), t) == 0 &&
            (s[t.size()] == '_' || s[t.size()] == '-' || s[t.size()] == '.'))
            return s.substr(t.size() + 1);
        return std::nullopt;
    };
    std::vector<std::pair<std::string, std::string>> found;
    for (const std::string& file : tsfStems) {
        const std::string s = fs::path(file).stem().string();
        std::optional<std::string> name = suffixOf(s, stem);
        if (!name) continue;
        bool longerOwner = std::any_of(tckStems.begin(), tckStems.end(), [&](const std::string& other) {
            return other.size() > stem.size() && suffixOf(s, other).has_value();
        });
        if (!longerOwner) found.emplace_back((dir / file).string(), *name);
    }
    std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    return found;
}

}  // namespace tc
