#include "core/scene.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/spec_reader.h"

namespace tc {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr float kInf = std::numeric_limits<float>::max();

// --set key.path=value: the value is JSON when it parses as JSON (numbers, booleans, arrays,
// quoted strings), a plain string otherwise, so `--set render.technique=rasterized` works.
void applyOverride(json& doc, const std::string& assignment, std::set<std::string>& overridden) {
    auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0)
        throw InputError("--set " + assignment + ": expected key.path=value");
    std::string path = assignment.substr(0, eq);
    std::string text = assignment.substr(eq + 1);
    json value = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (value.is_discarded()) value = text;

    json* node = &doc;
    std::size_t start = 0;
    std::string walked;
    while (true) {
        auto dot = path.find('.', start);
        std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        if (key.empty()) throw InputError("--set " + assignment + ": empty key in \"" + path + "\"");
        if (!node->is_object())
            throw InputError("--set " + assignment + ": \"" + walked + "\" is not an object, cannot set \"" + path + "\"");
        walked += (walked.empty() ? "" : ".") + key;
        if (dot == std::string::npos) {
            (*node)[key] = value;
            break;
        }
        if (!node->contains(key)) (*node)[key] = json::object();
        node = &(*node)[key];
        start = dot + 1;
    }
    overridden.insert(path);
}

RangeSpec readRange(SpecReader& r, const std::string& key) {
    RangeSpec range;
    if (!r.has(key)) return range;
    const json& v = r.raw(key);
    if (v.is_string() && v.get<std::string>() == "auto") return range;
    if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number() &&
        std::isfinite(v[0].get<double>()) && std::isfinite(v[1].get<double>()) &&
        v[0].get<double>() < v[1].get<double>()) {
        range.automatic = false;
        range.lo = v[0].get<float>();
        range.hi = v[1].get<float>();
        return range;
    }
    r.fail(key, "expected \"auto\" or [min, max] with min < max, got " + describeJson(v));
}

void readDataset(SpecReader r, DatasetSpec& d, const std::set<std::string>& overridden) {
    bool hasPath = r.has("path"), hasGenerate = r.has("generate");
    if (hasPath == hasGenerate)
        r.fail(hasPath ? "path" : "generate", hasPath ? "give either \"path\" or \"generate\", not both"
                                                      : "missing: give \"path\" (a file) or \"generate\" (\"tornado\")");
    if (hasPath) {
        d.path = r.getString("path", "");
        if (d.path.empty()) r.fail("path", "expected a non-empty file path");
        // Paths in a scene file are relative to that file; paths given with --set to the cwd.
        if (fs::path(d.path).is_relative() && !r.file().empty() && !overridden.count("dataset.path") &&
            !overridden.count("dataset"))
            d.path = (fs::path(r.file()).parent_path() / d.path).lexically_normal().string();
    } else {
        d.generate = r.getEnum("generate", "tornado", {"tornado"});
        d.lines = r.getInt("lines", d.lines, 1, 10'000'000);
        d.points = r.getInt("points", d.points, 2, 10'000'000);
        d.seed = std::uint32_t(r.getInt("seed", int(d.seed), 0, std::numeric_limits<int>::max()));
        if (double(d.lines) * double(d.points) > 2e8)
            r.fail("points", "lines x points = " + std::to_string(double(d.lines) * d.points) +
                                 " exceeds the generator limit of 2e8 vertices");
    }
    r.finish();
}

void readStyle(SpecReader r, StyleSpec& s) {
    if (r.has("radius")) {
        const json& v = r.raw("radius");
        if (v.is_object()) {
            SpecReader m = r.child("radius");
            s.radius.attribute = m.getString("attribute", "");
            if (s.radius.attribute.empty()) m.fail("attribute", "missing: the point attribute to map to the radius");
            s.radius.range = readRange(m, "range");
            glm::vec4 rr{s.radius.radiusLo, s.radius.radiusHi, 0, 0};
            if (m.has("radius_range")) {
                const json& a = m.raw("radius_range");
                if (!(a.is_array() && a.size() == 2 && a[0].is_number() && a[1].is_number() &&
                      a[0].get<double>() > 0 && a[1].get<double>() > 0 && std::isfinite(a[0].get<double>()) &&
                      std::isfinite(a[1].get<double>())))
                    m.fail("radius_range", "expected [r_min, r_max] with positive radii, got " + describeJson(a));
                rr = {a[0].get<float>(), a[1].get<float>(), 0, 0};
            }
            s.radius.radiusLo = rr.x;
            s.radius.radiusHi = rr.y;
            m.finish();
        } else {
            s.radius.constant = r.getFloat("radius", s.radius.constant, 1e-9f, kInf);
        }
    }
    if (r.has("color")) {
        const json& v = r.raw("color");
        if (v.is_object()) {
            SpecReader m = r.child("color");
            s.color.attribute = m.getString("attribute", "");
            if (s.color.attribute.empty()) m.fail("attribute", "missing: the point attribute to colour by");
            s.color.colormap = m.getEnum("colormap", s.color.colormap,
                                         {"viridis", "inferno", "magma", "plasma", "turbo", "cool_warm", "grayscale"});
            s.color.range = readRange(m, "range");
            m.finish();
        } else {
            // getColor takes RGBA too; an alpha here would be dropped silently.
            if (v.is_array() && v.size() == 4)
                r.fail("color", "expected a colour [r, g, b] with components in [0, 1] (opacity goes in style.opacity), got " +
                                    describeJson(v));
            s.color.constant = glm::vec3(r.getColor("color", glm::vec4(s.color.constant, 1.0f)));
        }
    }
    if (r.has("opacity")) {
        const json& v = r.raw("opacity");
        if (v.is_object()) {
            SpecReader m = r.child("opacity");
            s.opacity.attribute = m.getString("attribute", "");
            if (s.opacity.attribute.empty()) m.fail("attribute", "missing: the point attribute to map to opacity");
            s.opacity.range = readRange(m, "range");
            if (m.has("points")) {
                const json& p = m.raw("points");
                std::string expected = "expected [[t, opacity], ...] with at least 2 points, t ascending in [0, 1], opacity in [0, 1]";
                bool ok = p.is_array() && p.size() >= 2;
                std::vector<glm::vec2> points;
                for (std::size_t i = 0; ok && i < p.size(); ++i) {
                    ok = p[i].is_array() && p[i].size() == 2 && p[i][0].is_number() && p[i][1].is_number();
                    if (!ok) break;
                    glm::vec2 q{p[i][0].get<float>(), p[i][1].get<float>()};
                    ok = q.x >= 0 && q.x <= 1 && q.y >= 0 && q.y <= 1 && (points.empty() || q.x >= points.back().x);
                    points.push_back(q);
                }
                if (!ok) m.fail("points", expected + ", got " + describeJson(p));
                s.opacity.points = points;
            }
            m.finish();
        } else {
            s.opacity.constant = r.getFloat("opacity", s.opacity.constant, 0.0f, 1.0f);
        }
    }
    r.finish();
}

void readCamera(SpecReader r, CameraSpec& c) {
    Camera& cam = c.camera;
    cam.eye = r.getVec3("eye", cam.eye);
    cam.target = r.getVec3("target", cam.target);
    cam.up = r.getVec3("up", cam.up);
    cam.fovYDeg = r.getFloat("fov_deg", cam.fovYDeg, 1.0f, 170.0f);
    cam.projection = r.getEnum("projection", "perspective", {"perspective", "orthographic"}) == "orthographic"
                         ? Projection::Orthographic
                         : Projection::Perspective;
    cam.orthoHeight = r.getFloat("ortho_height", cam.orthoHeight, 1e-9f, kInf);
    c.fit = r.getBool("fit", false);
    if (glm::length(cam.target - cam.eye) < 1e-9f) r.fail("eye", "eye and target coincide");
    if (glm::length(cam.up) < 1e-9f) r.fail("up", "expected a non-zero vector");
    if (glm::length(glm::cross(cam.up, cam.target - cam.eye)) < 1e-6f * glm::length(cam.up) * glm::length(cam.target - cam.eye))
        r.fail("up", "is parallel to the viewing direction (target - eye)");
    r.finish();
}

void readAnimation(SpecReader r, AnimationSpec& a, const std::set<std::string>& overridden) {
    std::string type = r.getEnum("type", "none", {"none", "orbit", "keyframes"});
    if (type == "orbit") {
        a.type = AnimationSpec::Type::Orbit;
        a.frames = r.getInt("frames", 36, 1, 1'000'000);
        a.axis = r.getVec3("axis", a.axis);
        if (glm::length(a.axis) < 1e-9f) r.fail("axis", "expected a non-zero vector");
        a.degrees = r.getFloat("degrees", a.degrees, -1e6f, 1e6f);
    } else if (type == "keyframes") {
        a.type = AnimationSpec::Type::Keyframes;
        const json& keys = r.raw("keys");
        if (!keys.is_array() || keys.empty())
            r.fail("keys", "expected a non-empty array of {\"frame\", \"eye\", \"target\", \"up\"}");
        for (std::size_t i = 0; i < keys.size(); ++i) {
            SpecReader k(keys[i], r.file(), r.keyPath("keys[" + std::to_string(i) + "]"), &overridden);
            Keyframe key;
            key.frame = k.getInt("frame", -1, 0, 10'000'000);
            if (!k.has("frame")) k.fail("frame", "missing required key");
            if (!k.has("eye")) k.fail("eye", "missing required key");
            key.eye = k.getVec3("eye", key.eye);
            key.target = k.getVec3("target", key.target);
            key.up = k.getVec3("up", key.up);
            if (glm::length(key.target - key.eye) < 1e-9f) k.fail("eye", "eye and target coincide");
            if (!a.keys.empty() && key.frame <= a.keys.back().frame)
                k.fail("frame", "frames must increase: " + std::to_string(key.frame) + " after " +
                                    std::to_string(a.keys.back().frame));
            k.finish();
            a.keys.push_back(key);
        }
        a.frames = a.keys.back().frame + 1;
    }
    r.finish();
}

void readImage(SpecReader r, ImageSpec& im) {
    im.width = r.getInt("width", im.width, 1, 65536);
    im.height = r.getInt("height", im.height, 1, 65536);
    im.background = r.getColor("background", im.background);
    r.finish();
}

void readRender(SpecReader r, RenderSpec& rs) {
    r.getEnum("technique", "rasterized", {"rasterized"});
    rs.technique = RenderTechnique::Rasterized;
    std::string transparency =
        r.getEnum("transparency", "opaque", {"opaque", "kbuffer", "depth_peeling", "object_order"});
    rs.transparency = transparency == "kbuffer"         ? Transparency::KBuffer
                      : transparency == "depth_peeling" ? Transparency::DepthPeeling
                      : transparency == "object_order"  ? Transparency::ObjectOrder
                                                        : Transparency::Opaque;
    std::string billboards = r.getEnum("billboards", "compute", {"compute", "vertex", "geometry"});
    rs.billboards = billboards == "vertex"     ? BillboardPath::Vertex
                    : billboards == "geometry" ? BillboardPath::Geometry
                                               : BillboardPath::Compute;
    if (r.has("kbuffer")) {
        SpecReader k = r.child("kbuffer");
        rs.kbufferK = k.getInt("k", rs.kbufferK, 1, 16);
        k.finish();
    }
    rs.capClipping = r.getBool("cap_clipping", rs.capClipping);
    if (r.has("depth_peeling")) {
        SpecReader d = r.child("depth_peeling");
        rs.maxPeelLayers = d.getInt("max_layers", rs.maxPeelLayers, 0, 100000);
        d.finish();
    }
    rs.memoryBudgetMb = r.getInt("memory_budget_mb", rs.memoryBudgetMb, 1, 1 << 30);
    rs.referenceDepthPeeling = r.getEnum("reference", "none", {"none", "depth_peeling"}) == "depth_peeling";
    if (r.has("culling")) {
        SpecReader c = r.child("culling");
        rs.culling.enabled = c.getBool("enabled", true);
        rs.culling.slices = c.getInt("slices", rs.culling.slices, 1, 1024);
        rs.culling.opacityThreshold = c.getFloat("opacity_threshold", rs.culling.opacityThreshold, 0.0f, 1.0f);
        rs.culling.resortAngleDeg = c.getFloat("resort_angle_deg", rs.culling.resortAngleDeg, 0.0f, 180.0f);
        rs.culling.resortDistance = c.getFloat("resort_distance", rs.culling.resortDistance, 0.0f, 100.0f);
        c.finish();
    }
    if (r.has("ao")) {
        SpecReader a = r.child("ao");
        rs.ao.enabled = a.getBool("enabled", true);
        rs.ao.resolution = a.getInt("resolution", rs.ao.resolution, 8, 1024);
        rs.ao.cones = a.getInt("cones", rs.ao.cones, 1, 16);
        rs.ao.apertureDeg = a.getFloat("aperture_deg", rs.ao.apertureDeg, 10.0f, 90.0f);
        rs.ao.distance = a.getFloat("distance", rs.ao.distance, 1e-4f, 10.0f);
        rs.ao.strength = a.getFloat("strength", rs.ao.strength, 0.0f, 100.0f);
        a.finish();
    }
    r.finish();
}

void readLighting(SpecReader r, LightingSpec& l) {
    l.direction = r.getVec3("direction", l.direction);
    if (glm::length(l.direction) < 1e-9f) r.fail("direction", "expected a non-zero vector");
    l.ambient = r.getFloat("ambient", l.ambient, 0.0f, 100.0f);
    l.diffuse = r.getFloat("diffuse", l.diffuse, 0.0f, 100.0f);
    l.specular = r.getFloat("specular", l.specular, 0.0f, 100.0f);
    l.shininess = r.getFloat("shininess", l.shininess, 1.0f, 10000.0f);
    r.finish();
}

void readOutput(SpecReader r, OutputSpec& o) {
    o.dir = r.getString("dir", o.dir);
    if (o.dir.empty()) r.fail("dir", "expected a non-empty directory");
    o.name = r.getString("name", o.name);
    if (o.name.empty() || o.name.find('/') != std::string::npos)
        r.fail("name", "expected a file name pattern without '/', e.g. \"frame.####\"");
    auto formats = r.getStringList("formats", {"png", "exr"}, {"png", "exr"});
    if (formats.empty()) r.fail("formats", "expected at least one of \"png\", \"exr\"");
    o.png = o.exr = false;
    for (const auto& f : formats) (f == "png" ? o.png : o.exr) = true;
    auto aovs = r.getStringList("aovs", {"depth", "normal"}, {"depth", "normal", "id", "ao"});
    o.aovDepth = o.aovNormal = o.aovId = o.aovAo = false;
    for (const auto& a : aovs)
        (a == "depth" ? o.aovDepth : a == "normal" ? o.aovNormal : a == "id" ? o.aovId : o.aovAo) = true;
    o.timings = r.getBool("timings", o.timings);
    r.finish();
}

}  // namespace

int Scene::frameCount() const { return animation.type == AnimationSpec::Type::None ? 1 : animation.frames; }

// "{frame}", "{frame:04}", "{frame:4}". hasFrameToken must accept exactly what frameFileName
// replaces, or a multi-frame render with "{frame:x}" would write every frame to one name.
static const std::regex& frameBraces() {
    static const std::regex braces(R"(\{frame(?::0?(\d+))?\})");
    return braces;
}

bool hasFrameToken(const std::string& pattern) {
    return pattern.find('#') != std::string::npos || std::regex_search(pattern, frameBraces());
}

std::string frameFileName(const std::string& pattern, int frame) {
    std::smatch m;
    if (std::regex_search(pattern, m, frameBraces())) {
        int width = m[1].matched ? std::stoi(m[1].str()) : 0;
        std::string number = std::to_string(frame);
        if (int(number.size()) < width) number.insert(0, std::size_t(width) - number.size(), '0');
        return m.prefix().str() + number + m.suffix().str();
    }
    auto first = pattern.find('#');
    if (first == std::string::npos) return pattern;
    auto last = pattern.find_first_not_of('#', first);
    std::size_t width = (last == std::string::npos ? pattern.size() : last) - first;
    std::string number = std::to_string(frame);
    if (number.size() < width) number.insert(0, width - number.size(), '0');
    return pattern.substr(0, first) + number + (last == std::string::npos ? "" : pattern.substr(last));
}

Scene parseScene(const json& input, const std::string& file, const std::vector<std::string>& overrides) {
    json doc = input;
    std::set<std::string> overridden;
    if (!doc.is_object()) throw InputError((file.empty() ? "scene" : file) + ": expected a JSON object at the top level");
    for (const auto& o : overrides) applyOverride(doc, o, overridden);

    Scene scene;
    scene.file = file;
    SpecReader top(doc, file, "", &overridden);
    if (!top.has("dataset")) top.fail("dataset", "missing required key (\"path\" to a file or \"generate\": \"tornado\")");
    readDataset(top.child("dataset"), scene.dataset, overridden);
    if (top.has("style")) readStyle(top.child("style"), scene.style);
    if (top.has("camera")) readCamera(top.child("camera"), scene.camera);
    else scene.camera.fit = true;
    if (top.has("animation")) readAnimation(top.child("animation"), scene.animation, overridden);
    if (top.has("image")) readImage(top.child("image"), scene.image);
    if (top.has("render")) readRender(top.child("render"), scene.render);
    if (top.has("lighting")) readLighting(top.child("lighting"), scene.lighting);
    if (top.has("output")) readOutput(top.child("output"), scene.output);
    top.getString("$schema", "");  // allowed for editor support, ignored
    top.getString("description", "");
    top.finish();

    if (scene.frameCount() > 1 && !hasFrameToken(scene.output.name)) {
        SpecReader o(doc.contains("output") ? doc["output"] : json::object(), file, "output", &overridden);
        o.fail("name", "\"" + scene.output.name + "\" has no frame token ('####' or '{frame:04}') but the animation has " +
                           std::to_string(scene.frameCount()) + " frames");
    }
    if (scene.output.aovAo && !scene.render.ao.enabled) {
        SpecReader o(doc.contains("output") ? doc["output"] : json::object(), file, "output", &overridden);
        o.fail("aovs", "\"ao\" needs ambient occlusion: set render.ao.enabled to true");
    }
    scene.resolved = doc;
    return scene;
}

Scene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::error_code ec;
        if (!fs::exists(path, ec)) throw InputError(path + ": no such file");
        throw InputError(path + ": cannot read");
    }
    std::stringstream buffer;
    buffer << in.rdbuf();
    std::string text = buffer.str();
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::parse_error& e) {
        // nlohmann reports a byte offset; users want line:column.
        std::size_t offset = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
        std::size_t line = 1, column = 1;
        for (std::size_t i = 0; i < offset; ++i) {
            if (text[i] == '\n') { ++line; column = 1; } else ++column;
        }
        std::string what = e.what();
        auto colon = what.find("syntax error");
        throw InputError(path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": invalid JSON: " +
                         (colon != std::string::npos ? what.substr(colon) : what));
    }
    return parseScene(doc, path, overrides);
}

}  // namespace tc
