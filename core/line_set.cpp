#include "core/line_set.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace tc {

// Ranges and bounds are parallel reductions: they run over every vertex of every load (10^7
// vertices of a .tcb), and min/max are exact in any order, so the result does not depend on the
// thread count.
void Attribute::updateRange() {
    constexpr float inf = std::numeric_limits<float>::infinity();
    using MinMax = std::pair<float, float>;
    MinMax r = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, values.size(), 1 << 16), MinMax{inf, -inf},
        [&](const tbb::blocked_range<std::size_t>& range, MinMax m) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                float v = values[i];
                if (!std::isfinite(v)) continue;
                m.first = std::min(m.first, v);
                m.second = std::max(m.second, v);
            }
            return m;
        },
        [](MinMax a, MinMax b) {
            return MinMax{std::min(a.first, b.first), std::max(a.second, b.second)};
        });
    bool found = r.first <= r.second;
    min = found ? r.first : std::numeric_limits<float>::quiet_NaN();
    max = found ? r.second : std::numeric_limits<float>::quiet_NaN();
}

const Attribute* LineSet::attribute(const std::string& name) const {
    for (const Attribute& a : attributes)
        if (a.name == name) return &a;
    return nullptr;
}

void LineSet::updateBounds() {
    bounds = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, positions.size(), 1 << 16), Bounds{},
        [&](const tbb::blocked_range<std::size_t>& range, Bounds b) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) b.extend(positions[i]);
            return b;
        },
        [](Bounds a, const Bounds& b) {
            if (!b.empty()) {
                a.extend(b.lo);
                a.extend(b.hi);
            }
            return a;
        });
}

namespace {

std::string countNoun(std::size_t n, const char* singular, const char* plural) {
    return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

bool isFinite(const glm::vec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// True when cleanLineSet would change anything: a polyline with fewer than 2 vertices, a
// non-finite vertex or a zero-length segment.
bool needsCleaning(const LineSet& lines) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, lines.polylineCount(), 256), false,
        [&](const tbb::blocked_range<std::size_t>& range, bool found) {
            for (std::size_t p = range.begin(); p != range.end() && !found; ++p) {
                std::size_t begin = lines.offsets[p], end = lines.offsets[p + 1];
                if (end < begin + 2) return true;
                for (std::size_t v = begin; v < end; ++v) {
                    if (!isFinite(lines.positions[v])) return true;
                    if (v > begin && lines.positions[v] == lines.positions[v - 1]) return true;
                }
            }
            return found;
        },
        [](bool a, bool b) { return a || b; });
}

}  // namespace

std::string CleanReport::summary() const {
    std::string parts;
    auto add = [&](const std::string& part) {
        if (!parts.empty()) parts += ", ";
        parts += part;
    };
    if (nonFiniteVertices)
        add(countNoun(nonFiniteVertices, "non-finite vertex", "non-finite vertices") + " (polylines split there)");
    if (duplicateVertices)
        add(countNoun(duplicateVertices, "duplicate vertex", "duplicate vertices") + " (zero-length segments)");
    if (droppedPolylines) add(countNoun(droppedPolylines, "polyline", "polylines") + " with fewer than 2 vertices");
    std::string text = parts.empty() ? std::string() : "skipped " + parts;
    for (const std::string& warning : warnings) text += (text.empty() ? "" : "; ") + warning;
    return text;
}

CleanReport cleanLineSet(LineSet& lines) {
    TC_CHECK(!lines.offsets.empty());
    TC_CHECK_OP(std::size_t(lines.offsets.back()), ==, lines.positions.size());
    for (const Attribute& a : lines.attributes) TC_CHECK_OP(a.values.size(), ==, lines.positions.size());

    // Most inputs (every .tcb that `tubecast convert` wrote, every generator) are already clean:
    // a parallel read-only scan finds that out at memory speed and skips the serial compaction.
    if (!needsCleaning(lines)) {
        for (Attribute& a : lines.attributes) a.updateRange();
        lines.updateBounds();
        return {};
    }

    CleanReport report;
    // Compacts in place: `out` never overtakes the vertex being read, so positions and
    // attribute values can be moved down without a second buffer (line sets can be large).
    std::size_t out = 0;
    std::vector<std::uint32_t> offsets{0};
    offsets.reserve(lines.offsets.size());
    auto keep = [&](std::size_t from) {
        lines.positions[out] = lines.positions[from];
        for (Attribute& a : lines.attributes) a.values[out] = a.values[from];
        ++out;
    };
    // Closes the piece [offsets.back(), out): kept when it has a segment, rolled back otherwise.
    auto closePiece = [&] {
        std::size_t begin = offsets.back();
        if (out - begin >= 2) {
            offsets.push_back(std::uint32_t(out));
        } else if (out - begin == 1) {
            out = begin;
            ++report.droppedPolylines;
        }
    };

    for (std::size_t p = 0; p + 1 < lines.offsets.size(); ++p) {
        std::size_t begin = lines.offsets[p], end = lines.offsets[p + 1];
        TC_CHECK_OP(begin, <=, end);
        std::size_t piecesBefore = offsets.size();
        std::size_t droppedBefore = report.droppedPolylines;
        for (std::size_t v = begin; v < end; ++v) {
            const glm::vec3 pos = lines.positions[v];
            if (!isFinite(pos)) {
                ++report.nonFiniteVertices;
                closePiece();
                continue;
            }
            if (out > offsets.back() && lines.positions[out - 1] == pos) {
                ++report.duplicateVertices;
                continue;
            }
            keep(v);
        }
        closePiece();
        // A polyline that left nothing at all (empty, or only non-finite vertices) is dropped
        // too; one that left 1-vertex pieces was already counted per piece.
        if (offsets.size() == piecesBefore && report.droppedPolylines == droppedBefore) ++report.droppedPolylines;
    }

    lines.positions.resize(out);
    lines.positions.shrink_to_fit();
    for (Attribute& a : lines.attributes) {
        a.values.resize(out);
        a.values.shrink_to_fit();
        a.updateRange();
    }
    lines.offsets = std::move(offsets);
    lines.updateBounds();
    return report;
}

}  // namespace tc
