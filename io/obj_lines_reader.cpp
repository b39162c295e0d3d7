// Wavefront .obj polylines ("l" elements), with per-vertex attributes in "vt" rows the way
// LineVis (github.com/chrismile/LineVis, src/Loaders/ObjLoader.cpp) reads and writes them:
// "vt a0 a1 ..." rows with one value per attribute, the i-th row belonging to the i-th "v",
// and an optional "a NAME NAME ..." line naming the attributes.
// Hand-written rather than a mesh library's: those (tinyobjloader, Assimp) drop or triangulate
// "l" elements and keep only 2-3 texture coordinates.
#include <charconv>
#include <cmath>
#include <limits>
#include <string_view>

#include "core/error.h"
#include "io/line_formats.h"

namespace tc {

namespace {

// A "vt" row with more values than this is not an attribute row of any writer we know.
constexpr std::size_t kMaxAttributes = 256;

bool isSpace(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// Splits a line into whitespace-separated tokens (views into the line).
void tokenize(std::string_view line, std::vector<std::string_view>& tokens) {
    tokens.clear();
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isSpace(line[i])) ++i;
        std::size_t b = i;
        while (i < line.size() && !isSpace(line[i])) ++i;
        if (i > b) tokens.push_back(line.substr(b, i - b));
    }
}

class ObjParser {
public:
    explicit ObjParser(const ByteSource& source) : m_source(source) {}

    LineSet parse() {
        const std::vector<std::uint8_t> bytes = m_source.readRest(0, "the file");
        std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        std::vector<std::string_view> tokens;
        std::size_t pos = 0;
        while (pos < text.size()) {
            std::size_t nl = text.find('\n', pos);
            std::string_view line = text.substr(pos, nl == std::string_view::npos ? text.size() - pos : nl - pos);
            pos = nl == std::string_view::npos ? text.size() : nl + 1;
            ++m_line;
            if (std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
            tokenize(line, tokens);
            if (tokens.empty()) continue;
            const std::string_view kw = tokens[0];
            if (kw == "v") {
                if (tokens.size() < 4) fail("\"v\" needs 3 coordinates");
                // v x y z [w] or v x y z r g b (vertex colours): only the position is used.
                m_positions.emplace_back(number(tokens[1]), number(tokens[2]), number(tokens[3]));
                for (std::size_t i = 4; i < tokens.size(); ++i) number(tokens[i]);
            } else if (kw == "vt") {
                vertexAttributes(tokens);
            } else if (kw == "a") {
                if (!m_names.empty()) fail("second \"a\" (attribute names) line");
                for (std::size_t i = 1; i < tokens.size(); ++i) m_names.emplace_back(tokens[i]);
                if (m_names.empty()) fail("\"a\" without attribute names");
                m_namesLine = m_line;
            } else if (kw == "l") {
                polyline(tokens);
            }
            // f, vn, vp, g, o, s, usemtl, mtllib, ...: not lines, ignored.
        }
        return finish();
    }

private:
    [[noreturn]] void fail(const std::string& message) const { m_source.failAtLine(m_line, message); }

    float number(std::string_view token) const {
        float v = 0;
        auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
        // Out-of-range values ("1e99") parse as +-Inf, which cleaning drops like any non-finite value.
        if (ec == std::errc::result_out_of_range && end == token.data() + token.size())
            return token[0] == '-' ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity();
        if (ec != std::errc() || end != token.data() + token.size())
            fail("expected a number, got \"" + std::string(token.substr(0, 40)) + "\"");
        return v;
    }

    void vertexAttributes(const std::vector<std::string_view>& tokens) {
        const std::size_t k = tokens.size() - 1;
        if (k == 0) fail("\"vt\" without values");
        if (k > kMaxAttributes)
            fail("\"vt\" with " + std::to_string(k) + " values (at most " + std::to_string(kMaxAttributes) + ")");
        if (m_rows == 0) {
            m_attributeCount = k;
        } else if (k != m_attributeCount) {
            fail("\"vt\" with " + std::to_string(k) + " values, earlier rows have " + std::to_string(m_attributeCount));
        }
        for (std::size_t i = 1; i < tokens.size(); ++i) m_rowValues.push_back(number(tokens[i]));
        ++m_rows;
    }

    // OBJ index: 1-based, negative counts back from the last one defined so far.
    std::size_t resolve(std::string_view token, std::size_t defined, const char* what) const {
        long long i = 0;
        auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), i);
        if (ec != std::errc() || end != token.data() + token.size() || i == 0)
            fail(std::string("expected a ") + what + " index (1-based, or negative), got \"" +
                 std::string(token.substr(0, 40)) + "\"");
        long long r = i > 0 ? i - 1 : static_cast<long long>(defined) + i;
        if (r < 0 || r >= static_cast<long long>(defined))
            fail(std::string(what) + " index " + std::to_string(i) + " out of range (" + std::to_string(defined) +
                 " defined so far)");
        return std::size_t(r);
    }

    void polyline(const std::vector<std::string_view>& tokens) {
        for (std::size_t i = 1; i < tokens.size(); ++i) {
            std::string_view ref = tokens[i];
            std::size_t slash = ref.find('/');
            const std::size_t v = resolve(ref.substr(0, slash), m_positions.size(), "vertex");
            std::size_t row = v;  // LineVis: the vt row of the same number
            bool explicitRow = false;
            // "v/t" and "v/t/n" name a vt row; "v" and "v//n" do not.
            if (slash != std::string_view::npos && slash + 1 < ref.size() && ref[slash + 1] != '/') {
                row = resolve(ref.substr(slash + 1, ref.find('/', slash + 1) - slash - 1), m_rows, "vt");
                explicitRow = true;
            }
            m_refs.push_back({v, row, explicitRow ? 0 : m_line});
        }
        m_ends.push_back(m_refs.size());
    }

    LineSet finish() {
        const std::size_t k = m_rows ? m_attributeCount : 0;
        if (!m_names.empty() && m_names.size() != k)
            m_source.failAtLine(m_namesLine, std::to_string(m_names.size()) +
                                                 " attribute names, but \"vt\" rows have " + std::to_string(k) +
                                                 " values");
        if (m_refs.size() > std::numeric_limits<std::uint32_t>::max())
            m_source.fail("more than 2^32 - 1 polyline vertices are not supported");
        // Every reference copies a position and a row: an index list that repeats one vertex can
        // expand a small file enormously.
        m_source.checkExpansion(std::uint64_t(m_refs.size()) * (12 + 4 * k), 0, "the polylines");

        LineSet lines;
        lines.positions.reserve(m_refs.size());
        lines.attributes.resize(k);
        for (std::size_t a = 0; a < k; ++a) {
            lines.attributes[a].name = m_names.empty() ? "vt_" + std::to_string(a) : m_names[a];
            lines.attributes[a].values.reserve(m_refs.size());
        }
        if (k) {
            std::vector<std::string> names;
            for (const Attribute& a : lines.attributes) names.push_back(a.name);
            makeNamesUnique(names);
            for (std::size_t a = 0; a < k; ++a) lines.attributes[a].name = names[a];
        }
        for (const Ref& r : m_refs) {
            lines.positions.push_back(m_positions[r.vertex]);
            if (!k) continue;
            // Without "/t" the row of the same number must exist (all vt rows are read by now,
            // so a file listing them after the "l" lines works too).
            if (r.implicitLine && r.row >= m_rows)
                m_source.failAtLine(r.implicitLine, "vertex " + std::to_string(r.row + 1) + " has no \"vt\" row (" +
                                                        std::to_string(m_rows) + " rows)");
            for (std::size_t a = 0; a < k; ++a) lines.attributes[a].values.push_back(m_rowValues[r.row * k + a]);
        }
        for (std::size_t end : m_ends) lines.offsets.push_back(std::uint32_t(end));
        return lines;
    }

    struct Ref {
        std::size_t vertex, row;
        std::size_t implicitLine;  // line of an "l" that gave no "/t" (0: explicit)
    };

    const ByteSource& m_source;
    std::size_t m_line = 0;
    std::vector<glm::vec3> m_positions;
    std::vector<float> m_rowValues;
    std::size_t m_rows = 0, m_attributeCount = 0;
    std::vector<std::string> m_names;
    std::size_t m_namesLine = 0;
    std::vector<Ref> m_refs;
    std::vector<std::size_t> m_ends;
};

}  // namespace

LineSet readObjLines(const ByteSource& source) {
    return ObjParser(source).parse();
}

}  // namespace tc
