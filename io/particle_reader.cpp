#include "io/particle_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "io/byte_source.h"
#include "io/particle_reader_elements.h"

namespace tc {

ParticleData readMmpld(const std::string& path, const std::string& bytes);  // particle_reader_mmpld.cpp

namespace {

std::string readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::error_code ec;
        throw InputError(path + (std::filesystem::exists(path, ec) ? ": cannot read" : ": no such file"));
    }
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Lines of a text file with 1-based numbers for messages; '\r' of CRLF files is dropped.
class Lines {
public:
    Lines(std::string path, const std::string& text) : m_path(std::move(path)) {
        std::size_t start = 0;
        while (start < text.size()) {
            std::size_t end = text.find('\n', start);
            if (end == std::string::npos) end = text.size();
            std::string line = text.substr(start, end - start);
            if (!line.empty() && line.back() == '\r') line.pop_back();
            m_lines.push_back(std::move(line));
            start = end + 1;
        }
    }
    bool done() const { return m_next >= m_lines.size(); }
    std::size_t remaining() const { return m_lines.size() - m_next; }
    std::size_t lineNumber() const { return m_next; }  // of the line next() returned last
    const std::string& next(const char* what) {
        if (done()) fail(m_lines.size() + 1, std::string("unexpected end of file, expected ") + what);
        return m_lines[m_next++];
    }
    const std::string& peek() const { return m_lines[m_next]; }
    [[noreturn]] void fail(std::size_t line, const std::string& message) const {
        throw InputError(m_path + ":" + std::to_string(line) + ": " + message);
    }
    [[noreturn]] void fail(const std::string& message) const { fail(m_next, message); }
    const std::string& path() const { return m_path; }

private:
    std::string m_path;
    std::vector<std::string> m_lines;
    std::size_t m_next = 0;
};

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::istringstream s(line);
    std::string t;
    while (s >> t) out.push_back(t);
    return out;
}

bool parseDouble(const std::string& s, double& v) {
    const char* b = s.data();
    const char* e = b + s.size();
    while (b < e && std::isspace(static_cast<unsigned char>(*b))) ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(e[-1]))) --e;
    if (b == e) return false;
    if (*b == '+') ++b;
    auto r = std::from_chars(b, e, v);
    return r.ec == std::errc() && r.ptr == e;
}

double number(const Lines& lines, const std::string& s, const char* what) {
    double v;
    if (!parseDouble(s, v))
        lines.fail(lines.lineNumber(), std::string("expected a number for ") + what + ", got \"" + s + "\"");
    return v;
}

// A count that must fit in the remaining lines (never allocate from an unchecked size field).
std::size_t countField(const Lines& lines, const std::string& s, std::size_t perItem, const char* what) {
    double v;
    if (!parseDouble(s, v) || v < 0 || v != std::floor(v))
        lines.fail(lines.lineNumber(), std::string("expected a non-negative integer ") + what + ", got \"" + s + "\"");
    if (v > double(lines.remaining()) / double(perItem))
        lines.fail(lines.lineNumber(), std::string(what) + " " + s + " exceeds the " +
                                           std::to_string(lines.remaining()) + " lines left in the file");
    return std::size_t(v);
}

void addElement(ParticleSet& f, const std::string& symbol) {
    ElementStyle e = elementStyle(symbol);
    f.radii.push_back(e.radius);
    f.colors.push_back(glm::vec4(e.color, 1.0f));
    f.radiiFrom = f.colorsFrom = Provenance::Elements;
    f.elementRadii.try_emplace(symbol, e.radius);
}

Attribute& attributeNamed(ParticleSet& f, const std::string& name) {
    for (Attribute& a : f.attributes)
        if (a.name == name) return a;
    f.attributes.push_back(Attribute{name, {}});
    return f.attributes.back();
}

// --- XYZ / extended XYZ ----------------------------------------------------------------------

struct XyzColumn {
    std::string name;
    char type;  // S, R, I, L
    int cols;
};

// "Properties=species:S:1:pos:R:3:radius:R:1" (extended XYZ); empty when the comment has none.
std::vector<XyzColumn> xyzProperties(const Lines& lines, const std::string& comment) {
    auto at = comment.find("Properties=");
    if (at == std::string::npos) return {};
    std::size_t end = comment.find_first_of(" \t", at);
    std::string spec = comment.substr(at + 11, end == std::string::npos ? std::string::npos : end - at - 11);
    std::vector<std::string> parts;
    std::size_t s = 0;
    while (true) {
        auto c = spec.find(':', s);
        parts.push_back(spec.substr(s, c == std::string::npos ? std::string::npos : c - s));
        if (c == std::string::npos) break;
        s = c + 1;
    }
    if (parts.size() % 3 != 0) lines.fail("extended XYZ Properties=" + spec + ": expected name:type:columns triples");
    std::vector<XyzColumn> cols;
    for (std::size_t i = 0; i < parts.size(); i += 3) {
        double n;
        const std::string& type = parts[i + 1];
        if (type.size() != 1 || std::string("SRIL").find(type[0]) == std::string::npos ||
            !parseDouble(parts[i + 2], n) || n < 1 || n > 64 || n != std::floor(n))
            lines.fail("extended XYZ Properties=" + spec + ": bad column \"" + parts[i] + ":" + type + ":" +
                       parts[i + 2] + "\"");
        cols.push_back({parts[i], type[0], int(n)});
    }
    return cols;
}

ParticleData readXyz(const std::string& path, const std::string& text) {
    Lines lines(path, text);
    ParticleData data;
    while (!lines.done()) {
        if (split(lines.peek()).empty()) {  // trailing blank lines
            lines.next("");
            continue;
        }
        const std::string& countLine = lines.next("the particle count");
        auto countTokens = split(countLine);
        if (countTokens.size() != 1)
            lines.fail("expected the particle count on a line of its own, got \"" + countLine + "\"");
        std::size_t n = countField(lines, countTokens[0], 1, "particle count");
        const std::string comment = lines.next("the comment line");
        auto columns = xyzProperties(lines, comment);
        const bool extended = !columns.empty();
        if (!extended) columns = {{"species", 'S', 1}, {"pos", 'R', 3}};
        std::size_t needed = 0;
        bool hasPos = false;
        for (const auto& c : columns) {
            needed += std::size_t(c.cols);
            hasPos |= c.name == "pos" && c.cols == 3;
        }
        if (!hasPos) lines.fail(lines.lineNumber(), "extended XYZ Properties has no pos:R:3 column");
        ParticleSet f;
        f.positions.reserve(n);
        for (std::size_t i = 0; i < n; ++i) {
            const std::string& line = lines.next("a particle line");
            auto t = split(line);
            if (t.size() < needed)
                lines.fail("expected " + std::to_string(needed) + " columns, got " + std::to_string(t.size()));
            std::size_t k = 0;
            glm::vec3 pos(0.0f);
            bool hadColor = false, hadRadius = false;
            glm::vec4 color(1.0f);
            for (const auto& c : columns) {
                if (c.type == 'S') {
                    if (c.name == "species" || c.name == "element") {
                        ElementStyle e = elementStyle(t[k]);
                        if (!hadRadius) {
                            f.radii.push_back(e.radius), hadRadius = true;
                            f.radiiFrom = Provenance::Elements;
                            f.elementRadii.try_emplace(t[k], e.radius);
                        }
                        color = glm::vec4(e.color, 1.0f);
                        hadColor = true;
                        if (f.colorsFrom == Provenance::None) f.colorsFrom = Provenance::Elements;
                    }
                    k += std::size_t(c.cols);
                    continue;
                }
                for (int j = 0; j < c.cols; ++j, ++k) {
                    double v;
                    if (c.type == 'L')
                        v = (t[k] == "T" || t[k] == "True" || t[k] == "1") ? 1.0 : 0.0;
                    else
                        v = number(lines, t[k], c.name.c_str());
                    if (c.name == "pos")
                        pos[j] = float(v);
                    else if (c.name == "radius" && c.cols == 1) {
                        if (hadRadius)
                            f.radii.back() = float(v);
                        else
                            f.radii.push_back(float(v)), hadRadius = true;
                        f.radiiFrom = Provenance::File;
                    } else if ((c.name == "color" || c.name == "colour") && (c.cols == 3 || c.cols == 4)) {
                        color[j] = float(v);
                        hadColor = true;
                        f.colorsFrom = Provenance::File;
                    } else {
                        static const char* xyz[3] = {"_x", "_y", "_z"};
                        std::string name = c.cols == 1   ? c.name
                                           : c.cols == 3 ? c.name + xyz[j]
                                                         : c.name + "_" + std::to_string(j);
                        attributeNamed(f, name).values.push_back(float(v));
                    }
                }
            }
            if (!std::isfinite(pos.x) || !std::isfinite(pos.y) || !std::isfinite(pos.z))
                lines.fail("non-finite position");
            f.positions.push_back(pos);
            if (hadColor) f.colors.push_back(color);
            if ((hadColor && f.colors.size() != f.positions.size()) ||
                (hadRadius && f.radii.size() != f.positions.size()))
                lines.fail("radius/colour columns present for some particles only");
        }
        f.update();
        f.checkConsistent();
        data.frames.push_back(std::move(f));
    }
    if (data.frames.empty()) throw InputError(path + ": no particles (empty file)");
    return data;
}

// --- PDB --------------------------------------------------------------------------------------

std::string trim(const std::string& s) {
    auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) return "";
    auto e = s.find_last_not_of(" \t");
    return s.substr(b, e - b + 1);
}

std::string column(const std::string& line, std::size_t from1, std::size_t to1) {  // 1-based, inclusive
    if (line.size() < from1) return "";
    return line.substr(from1 - 1, std::min(line.size(), to1) - (from1 - 1));
}

ParticleData readPdb(const std::string& path, const std::string& text) {
    Lines lines(path, text);
    ParticleData data;
    ParticleSet current;
    bool inModel = false;
    auto finishFrame = [&]() {
        if (current.positions.empty()) return;
        current.update();
        data.frames.push_back(std::move(current));
        current = ParticleSet{};
    };
    while (!lines.done()) {
        const std::string& line = lines.next("");
        const std::string record = column(line, 1, 6);
        if (record.rfind("MODEL", 0) == 0) {
            finishFrame();
            inModel = true;
        } else if (record.rfind("ENDMDL", 0) == 0) {
            finishFrame();
            inModel = false;
        } else if (record == "ATOM  " || record == "HETATM") {
            if (line.size() < 54)
                lines.fail("ATOM/HETATM record shorter than 54 columns (x, y, z are in columns 31-54)");
            glm::vec3 p(float(number(lines, column(line, 31, 38), "x (columns 31-38)")),
                        float(number(lines, column(line, 39, 46), "y (columns 39-46)")),
                        float(number(lines, column(line, 47, 54), "z (columns 47-54)")));
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) lines.fail("non-finite position");
            std::string element = trim(column(line, 77, 78));
            if (element.empty()) element = elementFromAtomName(trim(column(line, 13, 16)), record == "HETATM");
            current.positions.push_back(p);
            addElement(current, element);
            double occupancy = 1.0, bfactor = 0.0, residue = 0.0;
            std::string occ = trim(column(line, 55, 60)), bf = trim(column(line, 61, 66)),
                        res = trim(column(line, 23, 26));
            if (!occ.empty()) occupancy = number(lines, occ, "occupancy (columns 55-60)");
            if (!bf.empty()) bfactor = number(lines, bf, "temperature factor (columns 61-66)");
            if (!res.empty() && !parseDouble(res, residue)) residue = std::nan("");  // hybrid-36 etc.
            attributeNamed(current, "occupancy").values.push_back(float(occupancy));
            attributeNamed(current, "b_factor").values.push_back(float(bfactor));
            attributeNamed(current, "residue").values.push_back(float(residue));
        }
    }
    (void)inModel;
    finishFrame();
    if (data.frames.empty()) throw InputError(path + ": no ATOM or HETATM records");
    return data;
}

// --- mmCIF (PDBx) ---------------------------------------------------------------------------

// Whitespace-separated CIF tokens of one line; '...' and "..." quote a token (the closing quote
// must be followed by whitespace or the end, so O5'' atom names survive), '#' starts a comment.
std::vector<std::string> cifTokens(const Lines& lines, const std::string& line) {
    std::vector<std::string> tokens;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i >= line.size() || line[i] == '#') break;
        if (line[i] == '\'' || line[i] == '"') {
            const char quote = line[i];
            std::size_t end = i + 1;
            while (end < line.size() &&
                   !(line[end] == quote &&
                     (end + 1 == line.size() || std::isspace(static_cast<unsigned char>(line[end + 1])))))
                ++end;
            if (end >= line.size()) lines.fail("unterminated quoted value");
            tokens.push_back(line.substr(i + 1, end - i - 1));
            i = end + 1;
        } else {
            std::size_t end = i;
            while (end < line.size() && !std::isspace(static_cast<unsigned char>(line[end]))) ++end;
            tokens.push_back(line.substr(i, end - i));
            i = end;
        }
    }
    return tokens;
}

// The atom_site loop of a PDBx/mmCIF file: Cartn_x/y/z (Angstrom), the element from type_symbol
// (else from the atom name), pdbx_PDB_model_num changes = frames; occupancy, B_iso_or_equiv and
// the residue number as attributes, as for PDB. '?' and '.' are missing values.
ParticleData readMmcif(const std::string& path, const std::string& text) {
    Lines lines(path, text);
    // Find "loop_" followed by _atom_site.* names.
    std::vector<std::string> names;
    while (!lines.done() && names.empty()) {
        if (trim(lines.next("")) != "loop_") continue;
        while (!lines.done() && trim(lines.peek()).rfind("_atom_site.", 0) == 0)
            names.push_back(trim(lines.next("")).substr(11));
    }
    if (names.empty()) throw InputError(path + ": no _atom_site loop (not a PDBx/mmCIF coordinate file?)");
    const std::size_t header = lines.lineNumber();
    auto index = [&](std::initializer_list<const char*> candidates) -> int {
        for (const char* c : candidates)
            for (std::size_t i = 0; i < names.size(); ++i)
                if (names[i] == c) return int(i);
        return -1;
    };
    const int x = index({"Cartn_x"}), y = index({"Cartn_y"}), z = index({"Cartn_z"});
    if (x < 0 || y < 0 || z < 0) lines.fail(header, "_atom_site loop without Cartn_x, Cartn_y and Cartn_z");
    const int element = index({"type_symbol"}), atomName = index({"label_atom_id", "auth_atom_id"});
    const int model = index({"pdbx_PDB_model_num"}), group = index({"group_PDB"});
    const int occupancy = index({"occupancy"}), bfactor = index({"B_iso_or_equiv"}),
              residue = index({"auth_seq_id", "label_seq_id"});

    ParticleData data;
    ParticleSet current;
    std::string currentModel;
    auto finishFrame = [&] {
        if (current.positions.empty()) return;
        current.update();
        data.frames.push_back(std::move(current));
        current = ParticleSet{};
    };
    auto value = [](const std::string& v) { return v == "?" || v == "." ? std::string() : v; };
    std::vector<std::string> row;
    while (!lines.done()) {
        const std::string next = trim(lines.peek());
        if (next.rfind("loop_", 0) == 0 || next.rfind("data_", 0) == 0 || (!next.empty() && next[0] == '_')) break;
        const std::string& line = lines.next("");
        if (!line.empty() && line[0] == ';') lines.fail("multi-line text fields are not supported in _atom_site");
        for (std::string& t : cifTokens(lines, line)) row.push_back(std::move(t));
        if (row.size() < names.size()) continue;  // a row may span lines
        if (row.size() > names.size())
            lines.fail(std::to_string(row.size()) + " values for " + std::to_string(names.size()) +
                       " _atom_site columns");
        const glm::vec3 p(float(number(lines, row[x], "Cartn_x")), float(number(lines, row[y], "Cartn_y")),
                          float(number(lines, row[z], "Cartn_z")));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) lines.fail("non-finite position");
        if (model >= 0 && row[model] != currentModel) {
            finishFrame();
            currentModel = row[model];
        }
        std::string symbol = element >= 0 ? value(row[element]) : std::string();
        if (symbol.empty() && atomName >= 0)
            symbol = elementFromAtomName(value(row[atomName]), group >= 0 && row[group] == "HETATM");
        current.positions.push_back(p);
        addElement(current, symbol);
        auto optional = [&](int column, double fallback, const char* what) {
            const std::string v = column >= 0 ? value(row[column]) : std::string();
            return v.empty() ? fallback : number(lines, v, what);
        };
        attributeNamed(current, "occupancy").values.push_back(float(optional(occupancy, 1.0, "occupancy")));
        attributeNamed(current, "b_factor").values.push_back(float(optional(bfactor, 0.0, "B_iso_or_equiv")));
        double res = std::nan("");
        if (residue >= 0 && !parseDouble(value(row[residue]), res)) res = std::nan("");
        attributeNamed(current, "residue").values.push_back(float(res));
        row.clear();
    }
    if (!row.empty())
        lines.fail("_atom_site loop ends inside a row (" + std::to_string(row.size()) + " of " +
                   std::to_string(names.size()) + " values)");
    finishFrame();
    if (data.frames.empty()) throw InputError(path + ": _atom_site loop without atoms");
    return data;
}

// --- LAMMPS text dump -------------------------------------------------------------------------

ParticleData readLammps(const std::string& path, const std::string& text) {
    Lines lines(path, text);
    ParticleData data;
    while (!lines.done()) {
        if (trim(lines.peek()).empty()) {
            lines.next("");
            continue;
        }
        std::size_t n = 0;
        bool haveCount = false, haveBox = false;
        glm::vec3 lo(0.0f), hi(1.0f);
        std::optional<double> time;
        // Items up to ATOMS, in any order.
        while (true) {
            const std::string item = trim(lines.next("ITEM: ATOMS"));
            if (item.rfind("ITEM:", 0) != 0) lines.fail("expected an \"ITEM:\" line, got \"" + item + "\"");
            if (item.rfind("ITEM: TIMESTEP", 0) == 0) {
                number(lines, trim(lines.next("the timestep")), "TIMESTEP");
            } else if (item == "ITEM: TIME") {  // dump_modify time yes: the simulation time
                time = number(lines, trim(lines.next("the time")), "TIME");
            } else if (item.rfind("ITEM: NUMBER OF ATOMS", 0) == 0) {
                const std::string count = trim(lines.next("the atom count"));
                n = countField(lines, count, 1, "atom count");
                haveCount = true;
            } else if (item.rfind("ITEM: BOX BOUNDS", 0) == 0) {
                for (int a = 0; a < 3; ++a) {
                    auto t = split(lines.next("box bounds"));
                    if (t.size() < 2) lines.fail("expected \"lo hi\" box bounds");
                    lo[a] = float(number(lines, t[0], "box lo"));
                    hi[a] = float(number(lines, t[1], "box hi"));
                }
                haveBox = true;
            } else if (item.rfind("ITEM: ATOMS", 0) == 0) {
                auto names = split(item.substr(11));
                if (!haveCount) lines.fail("ITEM: ATOMS before ITEM: NUMBER OF ATOMS");
                int ix = -1, iy = -1, iz = -1;
                bool scaled = false;
                int iRadius = -1, iDiameter = -1;
                for (std::size_t k = 0; k < names.size(); ++k) {
                    const std::string& c = names[k];
                    if (c == "x" || c == "xu")
                        ix = int(k);
                    else if (c == "y" || c == "yu")
                        iy = int(k);
                    else if (c == "z" || c == "zu")
                        iz = int(k);
                    else if (c == "xs" || c == "xsu")
                        ix = int(k), scaled = true;
                    else if (c == "ys" || c == "ysu")
                        iy = int(k), scaled = true;
                    else if (c == "zs" || c == "zsu")
                        iz = int(k), scaled = true;
                    else if (c == "radius")
                        iRadius = int(k);
                    else if (c == "diameter")
                        iDiameter = int(k);
                }
                if (ix < 0 || iy < 0 || iz < 0) lines.fail("ITEM: ATOMS has no x y z (or xs ys zs) columns");
                if (scaled && !haveBox)
                    lines.fail("scaled coordinates (xs ys zs) need ITEM: BOX BOUNDS before ITEM: ATOMS");
                if (n > lines.remaining())
                    lines.fail("NUMBER OF ATOMS " + std::to_string(n) + " exceeds the " +
                               std::to_string(lines.remaining()) + " lines left in the file");
                ParticleSet f;
                f.positions.reserve(n);
                for (std::size_t i = 0; i < n; ++i) {
                    auto t = split(lines.next("an atom line"));
                    if (t.size() != names.size())
                        lines.fail("expected " + std::to_string(names.size()) + " columns, got " +
                                   std::to_string(t.size()));
                    glm::vec3 p(float(number(lines, t[std::size_t(ix)], "x")),
                                float(number(lines, t[std::size_t(iy)], "y")),
                                float(number(lines, t[std::size_t(iz)], "z")));
                    if (scaled) p = lo + p * (hi - lo);
                    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                        lines.fail("non-finite position");
                    f.positions.push_back(p);
                    if (iRadius >= 0)
                        f.radii.push_back(float(number(lines, t[std::size_t(iRadius)], "radius")));
                    else if (iDiameter >= 0)
                        f.radii.push_back(0.5f * float(number(lines, t[std::size_t(iDiameter)], "diameter")));
                    if (iRadius >= 0 || iDiameter >= 0) f.radiiFrom = Provenance::File;
                    for (std::size_t k = 0; k < names.size(); ++k) {
                        if (int(k) == ix || int(k) == iy || int(k) == iz || int(k) == iRadius || int(k) == iDiameter ||
                            names[k] == "id" || names[k] == "element")
                            continue;
                        double v;
                        attributeNamed(f, names[k]).values.push_back(parseDouble(t[k], v) ? float(v) : std::nanf(""));
                    }
                }
                f.time = time;
                f.update();
                f.checkConsistent();
                data.frames.push_back(std::move(f));
                break;
            } else {
                lines.fail("unknown item \"" + item + "\"");
            }
        }
    }
    if (data.frames.empty()) throw InputError(path + ": no ITEM: ATOMS block");
    return data;
}

// --- GROMACS .gro -----------------------------------------------------------------------------

ParticleData readGro(const std::string& path, const std::string& text) {
    Lines lines(path, text);
    ParticleData data;
    while (!lines.done()) {
        if (trim(lines.peek()).empty()) {
            lines.next("");
            continue;
        }
        lines.next("the title line");
        std::size_t n = countField(lines, trim(lines.next("the atom count")), 1, "atom count");
        if (n + 1 > lines.remaining())
            lines.fail("atom count " + std::to_string(n) + " exceeds the lines left in the file");
        ParticleSet f;
        f.positions.reserve(n);
        for (std::size_t i = 0; i < n; ++i) {
            const std::string& line = lines.next("an atom line");
            if (line.size() < 44) lines.fail("atom line shorter than 44 columns (x, y, z are in columns 21-44)");
            // nm -> Angstrom, so element radii (Angstrom) fit.
            glm::vec3 p(float(number(lines, column(line, 21, 28), "x (columns 21-28)")),
                        float(number(lines, column(line, 29, 36), "y (columns 29-36)")),
                        float(number(lines, column(line, 37, 44), "z (columns 37-44)")));
            p *= 10.0f;
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) lines.fail("non-finite position");
            f.positions.push_back(p);
            addElement(f, elementFromAtomName(trim(column(line, 11, 15)),
                                              trim(column(line, 6, 10)) == trim(column(line, 11, 15))));
            double residue = 0;
            if (!parseDouble(column(line, 1, 5), residue)) residue = std::nan("");
            attributeNamed(f, "residue").values.push_back(float(residue));
        }
        auto box = split(lines.next("the box line"));
        if (box.size() != 3 && box.size() != 9) lines.fail("expected the box line (3 or 9 numbers)");
        for (const auto& b : box) number(lines, b, "box");
        f.update();
        data.frames.push_back(std::move(f));
    }
    if (data.frames.empty()) throw InputError(path + ": empty file");
    return data;
}

}  // namespace

bool isParticleFile(const std::string& path) {
    if (path.empty()) return false;
    const std::string ext = extensionLower(path);
    for (const char* e : {".xyz", ".extxyz", ".pdb", ".ent", ".cif", ".mmcif", ".lammpstrj", ".dump", ".gro", ".mmpld"})
        if (ext == e) return true;
    return false;
}

ParticleData readParticles(const std::string& path) {
    const std::string ext = extensionLower(path);
    const std::string text = readAll(path);
    ParticleData data;
    if (ext == ".xyz" || ext == ".extxyz")
        data = readXyz(path, text);
    else if (ext == ".pdb" || ext == ".ent")
        data = readPdb(path, text);
    else if (ext == ".cif" || ext == ".mmcif")
        data = readMmcif(path, text);
    else if (ext == ".lammpstrj" || ext == ".dump")
        data = readLammps(path, text);
    else if (ext == ".gro")
        data = readGro(path, text);
    else if (ext == ".mmpld")
        data = readMmpld(path, text);
    else
        throw InputError(
            path +
            ": not a particle format (.xyz, .extxyz, .pdb, .ent, .cif, .mmcif, .lammpstrj, .dump, .gro, .mmpld)");
    for (const ParticleSet& f : data.frames) f.checkConsistent();
    return data;
}

}  // namespace tc
