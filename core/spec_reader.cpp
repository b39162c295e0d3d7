#include "core/spec_reader.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.h"

namespace tc {

using nlohmann::json;

std::string describeJson(const json& value) {
    std::string s = value.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
}

SpecReader::SpecReader(const json& object, std::string file, std::string path, const std::set<std::string>* overridden)
    : m_object(object), m_file(std::move(file)), m_path(std::move(path)), m_overridden(overridden) {
    if (!m_object.is_object())
        throw InputError(m_file + ": " + (m_path.empty() ? std::string("top level") : m_path) +
                         ": expected an object, got " + describeJson(m_object));
}

std::string SpecReader::keyPath(const std::string& key) const {
    return m_path.empty() ? key : m_path + "." + key;
}

std::string SpecReader::location(const std::string& key) const {
    std::string path = keyPath(key);
    if (m_overridden)
        for (const auto& o : *m_overridden)
            if (path == o || path.rfind(o + ".", 0) == 0 || path.rfind(o + "[", 0) == 0 || o.rfind(path + ".", 0) == 0)
                return "--set " + path;
    return (m_file.empty() ? std::string("scene") : m_file) + ": " + path;
}

void SpecReader::fail(const std::string& key, const std::string& message) const {
    throw InputError(location(key) + ": " + message);
}

bool SpecReader::has(const std::string& key) const {
    m_known.insert(key);
    return m_object.contains(key);
}

const json& SpecReader::raw(const std::string& key) {
    if (!has(key)) fail(key, "missing required key");
    m_used.insert(key);
    return m_object.at(key);
}

SpecReader SpecReader::child(const std::string& key) {
    const json& v = raw(key);
    if (!v.is_object()) fail(key, "expected an object, got " + describeJson(v));
    return SpecReader(v, m_file, keyPath(key), m_overridden);
}

bool SpecReader::getBool(const std::string& key, bool fallback) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    if (!v.is_boolean()) fail(key, "expected true or false, got " + describeJson(v));
    return v.get<bool>();
}

int SpecReader::getInt(const std::string& key, int fallback, int lo, int hi) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    std::string expected = "expected integer " + std::to_string(lo) + ".." + std::to_string(hi);
    bool integral = v.is_number_integer() || (v.is_number_float() && std::isfinite(v.get<double>()) &&
                                              v.get<double>() == std::floor(v.get<double>()));
    if (!integral) fail(key, expected + ", got " + describeJson(v));
    double d = v.get<double>();
    if (d < lo || d > hi) fail(key, expected + ", got " + describeJson(v));
    return int(d);
}

float SpecReader::getFloat(const std::string& key, float fallback, float lo, float hi) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    auto range = [&] {
        std::string s = "expected a number";
        if (lo > -std::numeric_limits<float>::max() || hi < std::numeric_limits<float>::max()) {
            auto fmt = [](float x) {
                if (x >= std::numeric_limits<float>::max()) return std::string("inf");
                if (x <= -std::numeric_limits<float>::max()) return std::string("-inf");
                // 6 significant digits: the float bound, not its double expansion (1e-09, not
                // 9.999999717180685e-10), and "1", not "1.0".
                std::ostringstream s;
                s << x;
                return s.str();
            };
            s += " in [" + fmt(lo) + ", " + fmt(hi) + "]";
        }
        return s;
    };
    if (!v.is_number()) fail(key, range() + ", got " + describeJson(v));
    double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) fail(key, range() + ", got " + describeJson(v));
    return float(d);
}

std::string SpecReader::getString(const std::string& key, const std::string& fallback) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    if (!v.is_string()) fail(key, "expected a string, got " + describeJson(v));
    return v.get<std::string>();
}

static std::string joinQuoted(const std::vector<std::string>& values) {
    std::string s;
    for (std::size_t i = 0; i < values.size(); ++i) s += (i ? ", \"" : "\"") + values[i] + "\"";
    return s;
}

std::string SpecReader::getEnum(const std::string& key, const std::string& fallback,
                                const std::vector<std::string>& allowed) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    if (v.is_string())
        for (const auto& a : allowed)
            if (v.get<std::string>() == a) return a;
    fail(key, "expected one of " + joinQuoted(allowed) + ", got " + describeJson(v));
}

static bool numberArray(const json& v, std::size_t n) {
    if (!v.is_array() || v.size() != n) return false;
    for (const auto& e : v)
        if (!e.is_number() || !std::isfinite(e.get<double>())) return false;
    return true;
}

glm::vec3 SpecReader::getVec3(const std::string& key, glm::vec3 fallback) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    if (!numberArray(v, 3)) fail(key, "expected an array of 3 numbers, got " + describeJson(v));
    return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
}

glm::vec4 SpecReader::getVec4(const std::string& key, glm::vec4 fallback) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    if (!numberArray(v, 4)) fail(key, "expected an array of 4 numbers, got " + describeJson(v));
    return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>(), v[3].get<float>()};
}

glm::vec4 SpecReader::getColor(const std::string& key, glm::vec4 fallback) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    bool ok = numberArray(v, 3) || numberArray(v, 4);
    if (ok)
        for (const auto& e : v) ok = ok && e.get<double>() >= 0.0 && e.get<double>() <= 1.0;
    if (!ok) fail(key, "expected a colour [r, g, b] or [r, g, b, a] with components in [0, 1], got " + describeJson(v));
    return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>(), v.size() == 4 ? v[3].get<float>() : 1.0f};
}

std::vector<std::string> SpecReader::getStringList(const std::string& key, const std::vector<std::string>& fallback,
                                                   const std::vector<std::string>& allowed) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    std::string expected = "expected an array of strings from " + joinQuoted(allowed);
    if (!v.is_array()) fail(key, expected + ", got " + describeJson(v));
    std::vector<std::string> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
        bool known = false;
        if (v[i].is_string())
            for (const auto& a : allowed) known = known || v[i].get<std::string>() == a;
        if (!known) fail(key + "[" + std::to_string(i) + "]", expected + ", got " + describeJson(v[i]));
        out.push_back(v[i].get<std::string>());
    }
    return out;
}

// Levenshtein distance, for "did you mean" suggestions on a handful of short keys.
static std::size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            std::size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = row[j];
            row[j] = next;
        }
    }
    return row[b.size()];
}

void SpecReader::finish() const {
    for (const auto& [key, value] : m_object.items()) {
        if (m_used.count(key)) continue;
        std::string best;
        std::size_t bestDistance = 3;  // suggest only close matches
        for (const auto& k : m_known)
            if (std::size_t d = editDistance(key, k); d < bestDistance && !m_object.contains(k)) {
                best = k;
                bestDistance = d;
            }
        std::string message = "unknown key";
        if (!best.empty())
            message += " (did you mean \"" + best + "\"?)";
        else if (!m_known.empty())
            message += " (known keys: " + joinQuoted({m_known.begin(), m_known.end()}) + ")";
        fail(key, message);
    }
}

}  // namespace tc
