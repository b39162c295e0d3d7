#include "io/paraview_preset.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/json_file.h"

namespace tc {

using nlohmann::json;

std::string stripTrailingCommas(std::string_view text) {
    std::string out(text);
    bool inString = false;
    for (std::size_t i = 0; i < out.size(); ++i) {
        char c = out[i];
        if (inString) {
            if (c == '\\')
                ++i;  // skip the escaped character (\" must not end the string)
            else if (c == '"')
                inString = false;
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == ',') {
            std::size_t j = i + 1;
            while (j < out.size() && (out[j] == ' ' || out[j] == '\t' || out[j] == '\n' || out[j] == '\r')) ++j;
            if (j < out.size() && (out[j] == ']' || out[j] == '}')) out[i] = ' ';
        }
    }
    return out;
}

namespace {

[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& message) {
    throw InputError(source + ": " + (key.empty() ? "" : key + ": ") + message);
}

// A flat array of numbers in groups of `group`, at least two groups, first members ascending.
std::vector<double> readGroups(const json& preset, const char* key, std::size_t group, const std::string& source) {
    const json& v = preset.at(key);
    if (!v.is_array() || v.size() % group != 0 || v.size() < 2 * group)
        fail(source, key,
             "expected a flat array of " + std::to_string(group) + " numbers per point and at least 2 points, got " +
                 (v.is_array() ? std::to_string(v.size()) + " values" : std::string(v.type_name())));
    std::vector<double> values;
    values.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
            fail(source, std::string(key) + "[" + std::to_string(i) + "]",
                 "expected a finite number, got " + v[i].dump());
        values.push_back(v[i].get<double>());
    }
    for (std::size_t p = 1; p < values.size() / group; ++p)
        if (values[p * group] < values[(p - 1) * group])
            fail(source, std::string(key) + "[" + std::to_string(p * group) + "]",
                 "point positions must not decrease (" + std::to_string(values[p * group]) + " after " +
                     std::to_string(values[(p - 1) * group]) + ")");
    if (values[values.size() - group] == values[0])
        fail(source, key, "all points are at the same position; a colormap needs a range");
    return values;
}

void checkUnit(double v, const std::string& source, const std::string& key, std::size_t index, const char* what) {
    if (!(v >= 0 && v <= 1))
        fail(source, key + "[" + std::to_string(index) + "]",
             std::string(what) + " must be in [0, 1], got " + std::to_string(v));
}

// vtkPiecewiseFunction's value between two nodes at s in [0,1] for the first node's midpoint
// and sharpness (vtkPiecewiseFunction::GetTable): midpoint shifts where the half value is
// reached, sharpness goes from linear (0) through a Hermite curve to a step (1).
double shapedSegment(double y1, double y2, double s, double midpoint, double sharpness) {
    midpoint = std::clamp(midpoint, 1e-5, 1 - 1e-5);
    s = s < midpoint ? 0.5 * s / midpoint : 0.5 + 0.5 * (s - midpoint) / (1 - midpoint);
    if (sharpness > 0.99) return s < 0.5 ? y1 : y2;
    if (sharpness < 0.01) return (1 - s) * y1 + s * y2;
    if (s < 0.5)
        s = 0.5 * std::pow(s * 2, 1 + 10 * sharpness);
    else if (s > 0.5)
        s = 1 - 0.5 * std::pow((1 - s) * 2, 1 + 10 * sharpness);
    double ss = s * s, sss = ss * s;
    double h1 = 2 * sss - 3 * ss + 1, h2 = -2 * sss + 3 * ss, h3 = sss - 2 * ss + s, h4 = sss - ss;
    double tangent = (1 - sharpness) * (y2 - y1);
    return std::clamp(h1 * y1 + h2 * y2 + h3 * tangent + h4 * tangent, std::min(y1, y2), std::max(y1, y2));
}

}  // namespace

Colormap colormapFromParaViewPreset(const json& input, const std::string& source) {
    const json* p = &input;
    if (input.is_array()) {
        if (input.empty()) fail(source, "", "expected a preset object or a non-empty array of presets, got []");
        p = &input[0];
    }
    const json& preset = *p;
    if (!preset.is_object()) fail(source, "", std::string("expected a preset object, got ") + preset.type_name());
    if (!preset.contains("RGBPoints")) {
        if (preset.contains("IndexedColors"))
            fail(source, "IndexedColors", "categorical (indexed) presets are not supported; expected \"RGBPoints\"");
        fail(source, "RGBPoints", "missing: the colour control points [x, r, g, b, ...]");
    }

    Colormap map;
    if (preset.contains("Name") && preset["Name"].is_string()) map.name = preset["Name"].get<std::string>();
    if (map.name.empty()) map.name = std::filesystem::path(source).stem().string();

    if (preset.contains("ColorSpace")) {
        const json& cs = preset["ColorSpace"];
        std::string name = cs.is_string() ? cs.get<std::string>() : std::string();
        std::string lower = name;
        std::transform(lower.begin(), lower.end(), lower.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        if (lower == "rgb")
            map.space = ColorSpace::Rgb;
        else if (lower == "lab" || lower == "cielab" || lower == "lab/ciede2000")
            map.space = ColorSpace::Lab;
        else if (lower == "diverging")
            map.space = ColorSpace::Diverging;
        else if (lower == "hsv")
            map.space = ColorSpace::Hsv;
        else if (lower == "step")
            map.space = ColorSpace::Step;
        else
            fail(source, "ColorSpace",
                 "expected \"RGB\", \"Lab\", \"Diverging\", \"HSV\" or \"Step\", got " + cs.dump());
    }

    std::vector<double> rgb = readGroups(preset, "RGBPoints", 4, source);
    const double x0 = rgb[0], x1 = rgb[rgb.size() - 4];
    for (std::size_t i = 0; i < rgb.size(); i += 4) {
        for (std::size_t c = 1; c < 4; ++c) checkUnit(rgb[i + c], source, "RGBPoints", i + c, "colour components");
        map.t.push_back(float((rgb[i] - x0) / (x1 - x0)));
        map.srgb.push_back(glm::vec3(float(rgb[i + 1]), float(rgb[i + 2]), float(rgb[i + 3])));
    }
    map.t.front() = 0.0f;
    map.t.back() = 1.0f;

    if (preset.contains("NanColor")) {
        const json& nan = preset["NanColor"];
        if (!nan.is_array() || nan.size() < 3 || !nan[0].is_number() || !nan[1].is_number() || !nan[2].is_number())
            fail(source, "NanColor", "expected [r, g, b], got " + nan.dump());
        glm::vec3 c(nan[0].get<float>(), nan[1].get<float>(), nan[2].get<float>());
        for (int i = 0; i < 3; ++i) checkUnit(c[i], source, "NanColor", std::size_t(i), "colour components");
        map.nanColor = c;
    }

    if (preset.contains("Points")) {
        std::vector<double> pts = readGroups(preset, "Points", 4, source);
        const double a0 = pts[0], a1 = pts[pts.size() - 4];
        auto t = [&](double x) { return float((x - a0) / (a1 - a0)); };
        for (std::size_t i = 0; i < pts.size(); i += 4) {
            checkUnit(pts[i + 1], source, "Points", i + 1, "opacity");
            checkUnit(pts[i + 2], source, "Points", i + 2, "midpoint");
            checkUnit(pts[i + 3], source, "Points", i + 3, "sharpness");
        }
        for (std::size_t i = 0; i < pts.size(); i += 4) {
            map.opacity.push_back({t(pts[i]), float(pts[i + 1])});
            if (i + 4 >= pts.size()) break;
            double mid = pts[i + 2], sharp = pts[i + 3];
            if (mid == 0.5 && sharp == 0) continue;
            constexpr int kPieces = 16;
            for (int k = 1; k < kPieces; ++k) {
                double s = double(k) / kPieces;
                map.opacity.push_back({float(t(pts[i]) + s * (t(pts[i + 4]) - t(pts[i]))),
                                       float(shapedSegment(pts[i + 1], pts[i + 5], s, mid, sharp))});
            }
        }
        map.opacity.front().x = 0.0f;
        map.opacity.back().x = 1.0f;
    }
    validateColormap(map, source);
    return map;
}

json paraViewPresetFromColormap(const Colormap& map) {
    json preset = json::object();
    preset["Name"] = map.name;
    preset["ColorSpace"] = colorSpaceName(map.space);
    json rgb = json::array();
    for (std::size_t i = 0; i < map.t.size(); ++i)
        for (float v : {map.t[i], map.srgb[i].x, map.srgb[i].y, map.srgb[i].z}) rgb.push_back(double(v));
    preset["RGBPoints"] = rgb;
    if (map.nanColor) preset["NanColor"] = {double(map.nanColor->x), double(map.nanColor->y), double(map.nanColor->z)};
    if (!map.opacity.empty()) {
        json points = json::array();
        for (const glm::vec2& p : map.opacity)
            for (double v : {double(p.x), double(p.y), 0.5, 0.0}) points.push_back(v);
        preset["Points"] = points;
    }
    preset["Creator"] = "tubecast " TUBECAST_VERSION;
    return preset;
}

void writeParaViewPreset(const Colormap& map, const std::string& path) {
    writeJsonFile(path, json::array({paraViewPresetFromColormap(map)}));
}

Colormap readParaViewPreset(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot read: " + std::strerror(errno));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    json doc;
    try {
        doc = json::parse(stripTrailingCommas(text));
    } catch (const json::parse_error& e) {
        TextPosition pos = textPosition(text, e.byte > 0 ? e.byte - 1 : 0);
        std::string what = e.what();
        std::size_t colon = what.find("syntax error");
        throw InputError(path + ":" + std::to_string(pos.line) + ":" + std::to_string(pos.column) +
                         ": invalid JSON: " + (colon != std::string::npos ? what.substr(colon) : what));
    }
    return colormapFromParaViewPreset(doc, path);
}

void loadStylePresets(StyleSpec& style, const std::string& sceneFile) {
    if (style.color.preset || isBuiltinColormap(style.color.colormap)) return;
    try {
        style.color.preset = std::make_shared<const Colormap>(readParaViewPreset(style.color.colormap));
    } catch (const InputError& e) {
        throw InputError((sceneFile.empty() ? std::string("scene") : sceneFile) +
                         ": style.color.colormap: " + e.what());
    }
}

}  // namespace tc
