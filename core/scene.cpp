#include "core/scene.h"

#include <algorithm>
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
    if (eq == std::string::npos || eq == 0) throw InputError("--set " + assignment + ": expected key.path=value");
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
            throw InputError("--set " + assignment + ": \"" + walked + "\" is not an object, cannot set \"" + path +
                             "\"");
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
    if (v.is_object() && v.size() == 1 && v.contains("percentiles")) {
        const json& p = v["percentiles"];
        if (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number() && p[0].get<double>() >= 0 &&
            p[0].get<double>() < p[1].get<double>() && p[1].get<double>() <= 100) {
            range.percentiles = true;
            range.percentileLo = p[0].get<float>();
            range.percentileHi = p[1].get<float>();
            return range;
        }
        r.fail(key, "percentiles: expected [p_lo, p_hi] with 0 <= p_lo < p_hi <= 100, got " + describeJson(p));
    }
    if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number() && std::isfinite(v[0].get<double>()) &&
        std::isfinite(v[1].get<double>()) && v[0].get<double>() < v[1].get<double>()) {
        range.automatic = false;
        range.lo = v[0].get<float>();
        range.hi = v[1].get<float>();
        return range;
    }
    r.fail(key,
           "expected \"auto\", [min, max] with min < max or {\"percentiles\": [p_lo, p_hi]}, got " + describeJson(v));
}

// dataset.trace (io/stream_tracer.h): streamlines of a vector field on the grid at dataset.path.
void readTrace(SpecReader r, TraceSpec& t) {
    if (!r.has("vector")) r.fail("vector", "missing: a 3-component point array name, or [\"vx\", \"vy\", \"vz\"]");
    const json& v = r.raw("vector");
    if (v.is_string() && !v.get<std::string>().empty()) {
        t.vector = v.get<std::string>();
    } else if (v.is_array() && v.size() == 3 && v[0].is_string() && v[1].is_string() && v[2].is_string() &&
               !v[0].get<std::string>().empty() && !v[1].get<std::string>().empty() &&
               !v[2].get<std::string>().empty()) {
        for (int i = 0; i < 3; ++i) t.components[std::size_t(i)] = v[std::size_t(i)].get<std::string>();
    } else {
        r.fail("vector", "expected a point array name or three scalar array names [\"vx\", \"vy\", \"vz\"], got " +
                             describeJson(v));
    }
    std::string seeding = r.getEnum("seeding", "random", {"random", "uniform", "line"});
    t.seeding = seeding == "uniform" ? TraceSpec::Seeding::Uniform
                : seeding == "line"  ? TraceSpec::Seeding::Line
                                     : TraceSpec::Seeding::Random;
    t.seeds = r.getInt("seeds", t.seeds, 1, 1'000'000);
    if (t.seeding == TraceSpec::Seeding::Line) {
        if (!r.has("line")) r.fail("line", "missing: seeding \"line\" needs \"line\": [[x0, y0, z0], [x1, y1, z1]]");
        const json& l = r.raw("line");
        auto isVec3 = [](const json& a) {
            return a.is_array() && a.size() == 3 && a[0].is_number() && a[1].is_number() && a[2].is_number();
        };
        if (!(l.is_array() && l.size() == 2 && isVec3(l[0]) && isVec3(l[1])))
            r.fail("line", "expected [[x0, y0, z0], [x1, y1, z1]], got " + describeJson(l));
        t.lineFrom = {l[0][0].get<float>(), l[0][1].get<float>(), l[0][2].get<float>()};
        t.lineTo = {l[1][0].get<float>(), l[1][1].get<float>(), l[1][2].get<float>()};
    }
    t.maxLength = r.getFloat("max_length", t.maxLength, 0.0f, kInf);
    std::string direction = r.getEnum("direction", "both", {"forward", "backward", "both"});
    t.direction = direction == "forward"    ? TraceSpec::Direction::Forward
                  : direction == "backward" ? TraceSpec::Direction::Backward
                                            : TraceSpec::Direction::Both;
    t.stepLength = r.getFloat("step", t.stepLength, 1e-4f, 10.0f);
    t.maxSteps = r.getInt("max_steps", t.maxSteps, 1, 1'000'000);
    t.randomSeed = std::uint32_t(r.getInt("random_seed", int(t.randomSeed), 0, std::numeric_limits<int>::max()));
    r.finish();
}

void readDataset(SpecReader r, DatasetSpec& d, const std::set<std::string>& overridden) {
    bool hasPath = r.has("path"), hasGenerate = r.has("generate");
    if (hasPath == hasGenerate)
        r.fail(hasPath ? "path" : "generate", hasPath
                                                  ? "give either \"path\" or \"generate\", not both"
                                                  : "missing: give \"path\" (a file) or \"generate\" (\"tornado\")");
    if (hasPath) {
        d.path = r.getString("path", "");
        if (d.path.empty()) r.fail("path", "expected a non-empty file path");
        // Paths in a scene file are relative to that file; paths given with --set to the cwd.
        if (fs::path(d.path).is_relative() && !r.file().empty() && !overridden.count("dataset.path") &&
            !overridden.count("dataset"))
            d.path = (fs::path(r.file()).parent_path() / d.path).lexically_normal().string();
        d.frame = r.getInt("frame", d.frame, -1, 10'000'000);  // time series (particles)
        if (r.has("trace")) readTrace(r.child("trace"), d.trace.emplace());
    } else {
        d.generate = r.getEnum("generate", "tornado",
                               {"tornado", "propeller", "brain", "convection", "turbulence", "spiral", "droplets"});
        if (d.generate == "droplets") {  // particles: "lines"/"points" do not apply
            d.particles = r.getInt("particles", d.particles, 1, 100'000'000);
            d.seed = std::uint32_t(r.getInt("seed", int(d.seed), 0, std::numeric_limits<int>::max()));
            d.frame = r.getInt("frame", d.frame, -1, 10'000'000);
            r.finish();
            return;
        }
        d.lines = r.getInt("lines", d.lines, 1, 10'000'000);
        d.points = r.getInt("points", d.points, 2, 10'000'000);
        d.seed = std::uint32_t(r.getInt("seed", int(d.seed), 0, std::numeric_limits<int>::max()));
        if (double(d.lines) * double(d.points) > 2e8)
            r.fail("points", "lines x points = " + std::to_string(double(d.lines) * d.points) +
                                 " exceeds the generator limit of 2e8 vertices");
    }
    r.finish();
}

void readStyle(SpecReader r, StyleSpec& s, const std::set<std::string>& overridden) {
    s.radius.fromScene = r.has("radius");
    s.color.fromScene = r.has("color");
    s.opacity.fromScene = r.has("opacity");
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
                if (!(a.is_array() && a.size() == 2 && a[0].is_number() && a[1].is_number() && a[0].get<double>() > 0 &&
                      a[1].get<double>() > 0 && std::isfinite(a[0].get<double>()) && std::isfinite(a[1].get<double>())))
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
            // A built-in name, or a ParaView preset file (io/paraview_preset.h loads it), relative
            // to the scene file like dataset.path.
            s.color.colormap = m.getString("colormap", s.color.colormap);
            if (!isBuiltinColormap(s.color.colormap)) {
                std::string names;
                for (const auto& n : builtinColormapNames()) names += (names.empty() ? "\"" : ", \"") + n + "\"";
                if (fs::path(s.color.colormap).extension() != ".json")
                    m.fail("colormap", "expected one of " + names + " or a ParaView preset file (.json), got \"" +
                                           s.color.colormap + "\"");
                if (fs::path(s.color.colormap).is_relative() && !r.file().empty() &&
                    !overridden.count("style.color.colormap") && !overridden.count("style.color") &&
                    !overridden.count("style"))
                    s.color.colormap =
                        (fs::path(r.file()).parent_path() / s.color.colormap).lexically_normal().string();
            }
            if (m.has("nan_color")) {
                if (m.raw("nan_color").is_array() && m.raw("nan_color").size() == 4)
                    m.fail("nan_color", "expected a colour [r, g, b] with components in [0, 1], got " +
                                            describeJson(m.raw("nan_color")));
                s.color.nanColor = glm::vec3(m.getColor("nan_color", glm::vec4(0.5f)));
            }
            s.color.range = readRange(m, "range");
            m.finish();
        } else if (v.is_string() && v.get<std::string>() == "direction") {
            s.color.direction = true;
        } else {
            // getColor takes RGBA too; an alpha here would be dropped silently.
            if (v.is_array() && v.size() == 4)
                r.fail("color",
                       "expected a colour [r, g, b] with components in [0, 1] (opacity goes in style.opacity), got " +
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
            if (m.has("points") && m.raw("points").is_string()) {
                if (m.raw("points").get<std::string>() != "colormap")
                    m.fail("points",
                           "expected [[t, opacity], ...] or \"colormap\" (the preset's opacity points), got " +
                               describeJson(m.raw("points")));
                s.opacity.pointsFromColormap = true;
            } else if (m.has("points")) {
                const json& p = m.raw("points");
                std::string expected =
                    "expected [[t, opacity], ...] with at least 2 points, t ascending in [0, 1], opacity in [0, 1]";
                if (!p.is_array() || p.size() < 2) m.fail("points", expected + ", got " + describeJson(p));
                std::vector<glm::vec2> points;
                for (std::size_t i = 0; i < p.size(); ++i) {
                    // The element is named so a long transfer function's bad point is found.
                    std::string at = "points[" + std::to_string(i) + "]";
                    if (!(p[i].is_array() && p[i].size() == 2 && p[i][0].is_number() && p[i][1].is_number()))
                        m.fail(at, "expected [t, opacity], got " + describeJson(p[i]));
                    glm::vec2 q{p[i][0].get<float>(), p[i][1].get<float>()};
                    if (!(q.x >= 0 && q.x <= 1)) m.fail(at, "t must be in [0, 1], got " + describeJson(p[i][0]));
                    if (!(q.y >= 0 && q.y <= 1)) m.fail(at, "opacity must be in [0, 1], got " + describeJson(p[i][1]));
                    if (!points.empty() && q.x < points.back().x)
                        m.fail(at,
                               "t must not decrease: " + describeJson(p[i][0]) + " after " + describeJson(p[i - 1][0]));
                    points.push_back(q);
                }
                s.opacity.points = points;
            }
            m.finish();
        } else {
            s.opacity.constant = r.getFloat("opacity", s.opacity.constant, 0.0f, 1.0f);
        }
    }
    if (r.has("halo")) {
        const json& v = r.raw("halo");
        if (v.is_boolean()) {
            s.halo.enabled = r.getBool("halo", false);
        } else if (v.is_object()) {
            SpecReader h = r.child("halo");
            s.halo.enabled = h.getBool("enabled", true);
            s.halo.width = h.getFloat("width", s.halo.width, 0.0f, 100.0f);
            if (!(s.halo.width > 0.0f)) h.fail("width", "expected a number in (0, 100] (tube radii)");
            s.halo.depth = h.getFloat("depth", s.halo.depth, 0.0f, 1e6f);
            if (h.has("color")) {
                if (h.raw("color").is_array() && h.raw("color").size() == 4)
                    h.fail("color",
                           "expected a colour [r, g, b] with components in [0, 1] (the halo takes the "
                           "line's opacity), got " +
                               describeJson(h.raw("color")));
                s.halo.color = glm::vec3(h.getColor("color", glm::vec4(0.0f)));
            }
            h.finish();
        } else {
            r.fail("halo", "expected true, false or {\"width\": w, \"depth\": d, \"color\": [r, g, b]}, got " +
                               describeJson(v));
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
    if (glm::length(glm::cross(cam.up, cam.target - cam.eye)) <
        1e-6f * glm::length(cam.up) * glm::length(cam.target - cam.eye))
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
    // Large images (core/tiling.h): "auto" or [nx, ny] with tiles at least 2 pixels wide.
    if (r.has("tiles")) {
        const json& t = r.raw("tiles");
        const bool isAuto = t.is_string() && t.get<std::string>() == "auto";
        const int maxX = std::max(1, im.width / 2), maxY = std::max(1, im.height / 2);
        auto inRange = [](const json& v, int hi) {
            return v.is_number_integer() && v.get<long long>() >= 1 && v.get<long long>() <= hi;
        };
        if (!isAuto && !(t.is_array() && t.size() == 2 && inRange(t[0], maxX) && inRange(t[1], maxY)))
            r.fail("tiles", "expected \"auto\" or [nx, ny] with integers 1.." + std::to_string(maxX) + " and 1.." +
                                std::to_string(maxY) + " (at most width/2 x height/2), got " + describeJson(t));
        im.tilesX = isAuto ? 0 : t[0].get<int>();
        im.tilesY = isAuto ? 0 : t[1].get<int>();
    }
    im.samples = r.getInt("samples", im.samples, 1, 1024);
    r.finish();
}

// render.opacity (docs/scene-spec.md, core/opacity_optimization.h).
void readOpacityOptimization(SpecReader o, OpacityOptimizationSpec& op) {
    op.segmentsPerLine = o.getInt("segments_per_line", op.segmentsPerLine, 1, 4096);
    op.p = o.getFloat("p", op.p, 0.0f, 1e6f);
    op.q = o.getFloat("q", op.q, 0.0f, 1e6f);
    op.r = o.getFloat("r", op.q / 10.0f, 0.0f, 1e6f);
    op.s = o.getFloat("s", op.s, 0.0f, 1e6f);
    op.lambda = o.getFloat("lambda", op.lambda, 0.0f, 100.0f);
    if (op.p <= 0.0f) o.fail("p", "expected a number > 0 (the energy must stay strictly convex)");
    op.blend = o.getFloat("blend", op.blend, 0.0f, 1.0f);
    if (op.blend <= 0.0f) o.fail("blend", "expected a number in (0, 1]");
    op.tolerance = o.getFloat("tolerance", op.tolerance, 1e-12f, 1.0f);
    op.maxIterations = o.getInt("max_iterations", op.maxIterations, 1, 1000000);
    op.dropBelow = o.getFloat("drop_below", op.dropBelow, 0.0f, 1.0f);
    op.dumpDir = o.getString("dump_dir", op.dumpDir);
    op.pipeline = o.getBool("pipeline", op.pipeline);
    if (op.pipeline && !op.dumpDir.empty())
        o.fail("pipeline", "a pipelined solve belongs to no one frame, so render.opacity.dump_dir must be empty");
    op.occlusionScale = o.getFloat("occlusion_scale", op.occlusionScale, 0.0f, 1.0f);
    if (!(op.occlusionScale > 0.0f)) o.fail("occlusion_scale", "expected a number in (0, 1]");
    op.coarseScale = o.getFloat("coarse_scale", op.coarseScale, 0.0f, 1.0f);
    if (op.coarseScale > 0.0f && !(op.coarseScale < op.occlusionScale)) {
        std::ostringstream m;
        m << "expected 0 (off) or a number below render.opacity.occlusion_scale (" << op.occlusionScale << "), got "
          << op.coarseScale;
        o.fail("coarse_scale", m.str());
    }
    {
        const std::string kind = o.getEnum("occlusion", "auto", {"auto", "assembled", "fragments"});
        op.occlusion = kind == "assembled"   ? OpacityOptimizationSpec::Occlusion::Assembled
                       : kind == "fragments" ? OpacityOptimizationSpec::Occlusion::Fragments
                                             : OpacityOptimizationSpec::Occlusion::Auto;
        if (op.occlusion == OpacityOptimizationSpec::Occlusion::Fragments && op.dropBelow > 0)
            o.fail("occlusion", "\"fragments\" never forms h_ij, so render.opacity.drop_below must be 0");
        if (op.occlusion == OpacityOptimizationSpec::Occlusion::Fragments && !op.dumpDir.empty())
            o.fail("occlusion", "\"fragments\" never assembles Q, which render.opacity.dump_dir writes");
    }
    if (o.has("importance")) {
        if (o.raw("importance").is_string()) {
            std::string kind = o.getEnum("importance", "constant", {"constant", "length", "curvature"});
            op.importance = kind == "length"      ? OpacityOptimizationSpec::Importance::Length
                            : kind == "curvature" ? OpacityOptimizationSpec::Importance::Curvature
                                                  : OpacityOptimizationSpec::Importance::Constant;
        } else if (o.raw("importance").is_object()) {
            SpecReader i = o.child("importance");
            if (!i.has("attribute")) i.fail("attribute", "missing required key");
            op.importance = OpacityOptimizationSpec::Importance::Attribute;
            op.attribute = i.getString("attribute", "");
            if (op.attribute.empty()) i.fail("attribute", "expected a point attribute name");
            if (!i.has("range")) i.fail("range", "missing required key (importance 0 and 1 at [a, b])");
            const nlohmann::json& range = i.raw("range");
            if (!range.is_array() || range.size() != 2 || !range[0].is_number() || !range[1].is_number() ||
                !(range[0].get<double>() < range[1].get<double>()))
                i.fail("range", "expected [a, b] with a < b, got " + describeJson(range));
            op.rangeLo = range[0].get<float>();
            op.rangeHi = range[1].get<float>();
            i.finish();
        } else {
            o.fail(
                "importance",
                "expected \"constant\", \"length\", \"curvature\" or {\"attribute\": NAME, \"range\": [a, b]}, got " +
                    describeJson(o.raw("importance")));
        }
    }
    o.finish();
}

// A transfer function of render.spheres.ambient_*: [[Theta, value], ...] with 2..16 points, Theta
// ascending in [0, 1], values in [0, 1].
std::vector<glm::vec2> readAmbientTransfer(SpecReader& r, const std::string& key, const std::string& value) {
    const json& p = r.raw(key);
    const std::string expected = "expected [[opacity, " + value + "], ...] with 2 to " +
                                 std::to_string(AmbientTransfer::kMaxPoints) +
                                 " points, opacity ascending in [0, 1], " + value + " in [0, 1]";
    if (!p.is_array() || p.size() < 2 || p.size() > std::size_t(AmbientTransfer::kMaxPoints))
        r.fail(key, expected + ", got " + describeJson(p));
    std::vector<glm::vec2> points;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::string at = key + "[" + std::to_string(i) + "]";
        if (!(p[i].is_array() && p[i].size() == 2 && p[i][0].is_number() && p[i][1].is_number()))
            r.fail(at, "expected [opacity, " + value + "], got " + describeJson(p[i]));
        const glm::vec2 q{p[i][0].get<float>(), p[i][1].get<float>()};
        if (!(q.x >= 0 && q.x <= 1)) r.fail(at, "opacity must be in [0, 1], got " + describeJson(p[i][0]));
        if (!(q.y >= 0 && q.y <= 1)) r.fail(at, value + " must be in [0, 1], got " + describeJson(p[i][1]));
        if (!points.empty() && q.x < points.back().x)
            r.fail(at, "opacity must not decrease: " + describeJson(p[i][0]) + " after " + describeJson(p[i - 1][0]));
        points.push_back(q);
    }
    return points;
}

// render.spheres (Staib, Grottel & Gumhold 2015).
void readSpheres(SpecReader r, SpheresSpec& s) {
    std::string density = r.getEnum("density", "constant", {"constant", "l2", "hollow_constant", "hollow_l2"});
    s.density = density == "l2"                ? SphereDensity::L2
                : density == "hollow_constant" ? SphereDensity::HollowConstant
                : density == "hollow_l2"       ? SphereDensity::HollowL2
                                               : SphereDensity::Constant;
    s.innerRadius = r.getFloat("inner_radius", s.innerRadius, 0.0f, 0.99f);
    s.alphaRv = r.getFloat("alpha_rv", s.alphaRv, 0.0f, 1.0f);
    s.alphaA = r.getFloat("alpha_a", s.alphaA, 0.0f, 1.0f);
    s.chunks = r.getInt("chunks", s.chunks, 1, 1024);
    s.earlyZThreshold = r.getFloat("early_z_threshold", s.earlyZThreshold, 0.0f, 1.0f);
    s.earlyZStats = r.getBool("early_z_stats", s.earlyZStats);
    s.points = r.getEnum("primitive", "points", {"points", "quads"}) == "points";
    if (r.has("ambient_opacity")) s.ambient.opacity = readAmbientTransfer(r, "ambient_opacity", "ambient opacity");
    if (r.has("ambient_emission")) s.ambient.emission = readAmbientTransfer(r, "ambient_emission", "emission factor");
    r.finish();
}

void readVrc(SpecReader r, VrcSpec& v) {
    v.resolution = r.getInt("resolution", v.resolution, 2, 1024);
    v.quantization = r.getInt("quantization", v.quantization, 0, 90);
    v.neighbors = r.getEnum("neighbors", "off", {"off", "on"}) == "on";
    v.opacityThreshold = r.getFloat("opacity_threshold", v.opacityThreshold, 0.01f, 1.0f);
    v.pathLengthOpacity = r.getBool("path_length_opacity", v.pathLengthOpacity);
    v.shadows = r.getBool("shadows", v.shadows);
    const std::string shadowMode = r.getEnum("shadow_mode", "soft", {"soft", "hard", "density_cone", "hard_tubes"});
    v.shadowMode = shadowMode == "hard"           ? VrcSpec::ShadowMode::Hard
                   : shadowMode == "density_cone" ? VrcSpec::ShadowMode::DensityCone
                   : shadowMode == "hard_tubes"   ? VrcSpec::ShadowMode::HardTubes
                                                  : VrcSpec::ShadowMode::Soft;
    v.shadowApertureDeg = r.getFloat("shadow_aperture_deg", v.shadowApertureDeg, 1.0f, 90.0f);
    v.shadowLevel = r.getInt("shadow_level", v.shadowLevel, 0, 10);
    if (r.has("ao")) {
        SpecReader a = r.child("ao");
        const std::string method = a.getEnum("method", "cone_traced", {"cone_traced", "density_rays", "precomputed"});
        v.ao.method = method == "density_rays"  ? VrcSpec::Ao::Method::DensityRays
                      : method == "precomputed" ? VrcSpec::Ao::Method::Precomputed
                                                : VrcSpec::Ao::Method::ConeTraced;
        v.ao.rays = a.getInt("rays", v.ao.rays, 1, 256);
        v.ao.sphereRays = a.getInt("sphere_rays", v.ao.sphereRays, 1, 1024);
        v.ao.radiusVoxels = a.getFloat("radius_voxels", v.ao.radiusVoxels, 1.0f, 64.0f);
        a.finish();
    }
    const std::string build = r.getEnum("build", "auto", {"auto", "cpu", "gpu"});
    v.build = build == "cpu" ? VrcSpec::Build::Cpu : build == "gpu" ? VrcSpec::Build::Gpu : VrcSpec::Build::Auto;
    v.encoding = r.getEnum("encoding", "compact16", {"compact16", "paper"}) == "paper" ? VrcSpec::Encoding::Paper
                                                                                       : VrcSpec::Encoding::Compact16;
    if (r.has("lod")) {
        SpecReader l = r.child("lod");
        v.lod.enabled = l.getBool("enabled", v.lod.enabled);
        v.lod.pixelFootprint = l.getFloat("pixel_footprint", v.lod.pixelFootprint, 0.0f, 1024.0f);
        v.lod.opacityStart = l.getFloat("opacity_start", v.lod.opacityStart, 0.0f, 1.0f);
        l.finish();
    }
    r.finish();
}

void readRender(SpecReader r, RenderSpec& rs) {
    // Any identifier: the registry (core/technique_registry.h) knows which names exist and which
    // combinations with the keys below it takes.
    rs.technique = RenderTechnique(r.getString("technique", "auto"));
    if (rs.technique.name().empty() ||
        rs.technique.name().find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
        r.fail("technique",
               "expected a technique name (tubecast techniques lists them), got \"" + rs.technique.name() + "\"");
    // A preset only changes defaults: the keys below still override what it sets.
    if (r.getEnum("preset", "none", {"none", "gross2020"}) == "gross2020") {
        // Groß & Gumhold 2020, Sect. 6: "all measurements for transparent rendering were
        // conducted with k = 4", culling in 10 depth slices (Sect. 4.3; the slice count and the
        // 0.95 opacity threshold are the defaults already), ambient occlusion cone traced for
        // every produced fragment (Sect. 5.3, 6.1), not interpolated from a per-segment cache.
        rs.kbufferK = 4;
        rs.culling.enabled = true;
        rs.ao.cache = AoSpec::Cache::None;
    }
    if (r.has("vrc")) readVrc(r.child("vrc"), rs.vrc);
    if (r.has("spheres")) readSpheres(r.child("spheres"), rs.spheres);
    if (r.has("raytraced")) {
        SpecReader rt = r.child("raytraced");
        rs.raytracedAlphaCutoff = rt.getFloat("alpha_cutoff", rs.raytracedAlphaCutoff, 0.01f, 1.0f);
        rs.raytracedExactSurface =
            rt.getEnum("surface", rs.raytracedExactSurface ? "exact" : "embree", {"embree", "exact"}) == "exact";
        rt.finish();
    }
    std::string transparency = r.getEnum(
        "transparency", "auto", {"auto", "opaque", "kbuffer", "depth_peeling", "object_order", "opacity_optimization"});
    rs.transparency = transparency == "auto"                   ? Transparency::Auto
                      : transparency == "kbuffer"              ? Transparency::KBuffer
                      : transparency == "depth_peeling"        ? Transparency::DepthPeeling
                      : transparency == "object_order"         ? Transparency::ObjectOrder
                      : transparency == "opacity_optimization" ? Transparency::OpacityOptimization
                                                               : Transparency::Opaque;
    std::string billboards = r.getEnum("billboards", "compute", {"compute", "vertex", "geometry"});
    rs.billboards = billboards == "vertex"     ? BillboardPath::Vertex
                    : billboards == "geometry" ? BillboardPath::Geometry
                                               : BillboardPath::Compute;
    rs.billboardShape = r.getEnum("billboard_shape", "gross2020", {"gross2020", "rectangle"}) == "rectangle"
                            ? BillboardShape::Rectangle
                            : BillboardShape::Gross2020;
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
    std::string reference = r.getEnum("reference", "none", {"none", "depth_peeling", "raytraced"});
    rs.referenceDepthPeeling = reference == "depth_peeling";
    rs.referenceRaytraced = reference == "raytraced";
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
        rs.ao.method = a.getEnum("method", "cone_traced", {"cone_traced", "ray_traced"}) == "ray_traced"
                           ? AoSpec::Method::RayTraced
                           : AoSpec::Method::ConeTraced;
        rs.ao.samples = a.getInt("samples", rs.ao.samples, 1, 1024);
        const char* cache = rs.ao.cache == AoSpec::Cache::None ? "none" : "precomputed";
        rs.ao.cache = a.getEnum("cache", cache, {"precomputed", "none"}) == "none" ? AoSpec::Cache::None
                                                                                   : AoSpec::Cache::Precomputed;
        a.finish();
    }
    if (r.has("opacity")) readOpacityOptimization(r.child("opacity"), rs.opacity);
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

// A position or size in fractions of the image: [x, y] with both in [0, 1].
glm::vec2 readFraction2(SpecReader& r, const std::string& key, glm::vec2 fallback, float lo) {
    if (!r.has(key)) return fallback;
    const json& v = r.raw(key);
    if (!(v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number() && v[0].get<double>() >= lo &&
          v[0].get<double>() <= 1 && v[1].get<double>() >= lo && v[1].get<double>() <= 1))
        r.fail(key, std::string("expected [x, y] fractions of the image in ") + (lo > 0 ? "(0, 1]" : "[0, 1]") +
                        ", got " + describeJson(v));
    return {v[0].get<float>(), v[1].get<float>()};
}

std::optional<glm::vec3> readTextColor(SpecReader& r, const std::string& key) {
    if (!r.has(key)) return std::nullopt;
    if (r.raw(key).is_string() && r.raw(key).get<std::string>() == "auto") return std::nullopt;
    if (r.raw(key).is_array() && r.raw(key).size() == 4)
        r.fail(key,
               "expected \"auto\" or a colour [r, g, b] with components in [0, 1], got " + describeJson(r.raw(key)));
    return glm::vec3(r.getColor(key, glm::vec4(1.0f)));
}

// overlay.legend / overlay.axes: true (the defaults), false (none) or an object of settings.
bool readSwitchOrObject(SpecReader& r, const std::string& key) {
    const json& v = r.raw(key);
    if (v.is_boolean()) return v.get<bool>();
    if (!v.is_object()) r.fail(key, "expected true, false or an object of settings, got " + describeJson(v));
    return true;
}

void readLegend(SpecReader r, LegendSpec& l) {
    l.vertical = r.getEnum("orientation", "vertical", {"vertical", "horizontal"}) == "vertical";
    if (!l.vertical) {  // along the bottom edge
        l.position = {0.2f, 0.1f};
        l.size = {0.6f, 0.04f};
    }
    l.position = readFraction2(r, "position", l.position, 0.0f);
    l.size = readFraction2(r, "size", l.size, 1e-6f);
    l.title = r.getString("title", l.title);
    l.ticks = r.getInt("ticks", l.ticks, 2, 20);
    l.fontSize = r.getFloat("font_size", l.fontSize, 0.005f, 0.5f);
    l.textColor = readTextColor(r, "text_color");
    l.directionKey = r.getBool("direction_key", l.directionKey);
    r.finish();
}

void readTextLabel(SpecReader r, TextLabelSpec& t) {
    if (!r.has("content")) r.fail("content", "missing: the label's text, e.g. \"frame {frame}\"");
    t.content = r.getString("content", "");
    std::string error;
    expandLabel(t.content, {}, &error);
    if (!error.empty()) r.fail("content", error);
    t.position = readFraction2(r, "position", t.position, 0.0f);
    t.size = r.getFloat("size", t.size, 0.005f, 0.5f);
    const std::string align = r.getEnum("align", "left", {"left", "center", "right"});
    t.align = align == "center" ? TextAlign::Center : align == "right" ? TextAlign::Right : TextAlign::Left;
    t.color = readTextColor(r, "color");
    r.finish();
}

void readAxes(SpecReader r, AxesSpec& a) {
    const std::string corner =
        r.getEnum("corner", "bottom_left", {"bottom_left", "bottom_right", "top_left", "top_right"});
    a.corner = corner == "bottom_right" ? Corner::BottomRight
               : corner == "top_left"   ? Corner::TopLeft
               : corner == "top_right"  ? Corner::TopRight
                                        : Corner::BottomLeft;
    a.size = r.getFloat("size", a.size, 0.01f, 0.3f);
    a.labels = r.getBool("labels", a.labels);
    r.finish();
}

// overlay (core/overlay.h): what is drawn onto the display outputs.
void readOverlay(SpecReader r, OverlaySpec& o, const std::set<std::string>& overridden) {
    if (r.has("legend") && readSwitchOrObject(r, "legend")) {
        o.legend.emplace();
        if (r.raw("legend").is_object()) readLegend(r.child("legend"), *o.legend);
    }
    if (r.has("text")) {
        const json& list = r.raw("text");
        if (!list.is_array())
            r.fail("text",
                   "expected an array of labels [{\"content\": \"frame {frame}\", ...}], got " + describeJson(list));
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string at = "text[" + std::to_string(i) + "]";
            if (!list[i].is_object()) r.fail(at, "expected a label {\"content\": ...}, got " + describeJson(list[i]));
            readTextLabel(SpecReader(list[i], r.file(), "overlay." + at, &overridden), o.text.emplace_back());
        }
    }
    if (r.has("axes") && readSwitchOrObject(r, "axes")) {
        o.axes.emplace();
        if (r.raw("axes").is_object()) readAxes(r.child("axes"), *o.axes);
    }
    o.inExr = r.getBool("in_exr", o.inExr);
    o.font = r.getString("font", o.font);
    if (o.font.empty()) r.fail("font", "expected the path of a TrueType font file");
    if (fs::path(o.font).is_relative() && !r.file().empty() && !overridden.count("overlay.font") &&
        !overridden.count("overlay"))
        o.font = (fs::path(r.file()).parent_path() / o.font).lexically_normal().string();
    r.finish();
}

void readVideo(SpecReader r, VideoSpec& v) {
    if (!r.has("file")) r.fail("file", "missing: the movie's file name, e.g. \"movie.mp4\"");
    v.file = r.getString("file", "");
    if (fs::path(v.file).extension() != ".mp4")
        r.fail("file", "expected a file name ending in .mp4 (H.264 in MP4), got \"" + v.file + "\"");
    v.fps = r.getInt("fps", v.fps, 1, 240);
    v.crf = r.getInt("crf", v.crf, 0, 51);
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
    if (r.has("video")) readVideo(r.child("video"), o.video.emplace());
    r.finish();
}

}  // namespace

int Scene::frameCount() const {
    return animation.type == AnimationSpec::Type::None ? 1 : animation.frames;
}

// "{frame}", "{frame:04}", "{frame:4}". hasFrameToken must accept exactly what frameFileName
// replaces, or a multi-frame render with "{frame:x}" would write every frame to one name.
static const std::regex& frameBraces() {
    static const std::regex braces(R"(\{frame(?::0?(\d+))?\})");
    return braces;
}

glm::vec3 haloColor(const HaloSpec& halo, const glm::vec4& background) {
    return halo.color ? *halo.color : glm::vec3(1.0f) - glm::vec3(background);
}

bool hasFrameToken(const std::string& pattern) {
    return pattern.find('#') != std::string::npos || std::regex_search(pattern, frameBraces());
}

const RenderTechnique RenderTechnique::Auto{"auto"};
const RenderTechnique RenderTechnique::Rasterized{"rasterized"};
const RenderTechnique RenderTechnique::Raytraced{"raytraced"};
const RenderTechnique RenderTechnique::Spheres{"spheres"};
const RenderTechnique RenderTechnique::VoxelRaycast{"voxel_raycast"};

std::ostream& operator<<(std::ostream& out, const RenderTechnique& t) {
    return out << '"' << t.name() << '"';
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
    if (!doc.is_object())
        throw InputError((file.empty() ? "scene" : file) + ": expected a JSON object at the top level");
    for (const auto& o : overrides) applyOverride(doc, o, overridden);

    Scene scene;
    scene.file = file;
    // A scene file's defaults (RenderSpec's own serve code that builds scenes).
    scene.render.technique = RenderTechnique::Auto;
    scene.render.transparency = Transparency::Auto;
    SpecReader top(doc, file, "", &overridden);
    if (!top.has("dataset"))
        top.fail("dataset", "missing required key (\"path\" to a file or \"generate\": \"tornado\")");
    readDataset(top.child("dataset"), scene.dataset, overridden);
    if (top.has("style")) readStyle(top.child("style"), scene.style, overridden);
    if (top.has("camera"))
        readCamera(top.child("camera"), scene.camera);
    else
        scene.camera.fit = true;
    if (top.has("animation")) readAnimation(top.child("animation"), scene.animation, overridden);
    if (top.has("image")) readImage(top.child("image"), scene.image);
    if (top.has("render")) readRender(top.child("render"), scene.render);
    if (top.has("lighting")) readLighting(top.child("lighting"), scene.lighting);
    if (top.has("output")) readOutput(top.child("output"), scene.output);
    if (top.has("overlay")) readOverlay(top.child("overlay"), scene.overlay, overridden);
    if (scene.output.video) scene.overlay.fps = float(scene.output.video->fps);
    top.getString("$schema", "");  // allowed for editor support, ignored
    top.getString("description", "");
    top.finish();

    if (scene.frameCount() > 1 && !hasFrameToken(scene.output.name)) {
        SpecReader o(doc.contains("output") ? doc["output"] : json::object(), file, "output", &overridden);
        o.fail("name", "\"" + scene.output.name +
                           "\" has no frame token ('####' or '{frame:04}') but the animation has " +
                           std::to_string(scene.frameCount()) + " frames");
    }
    if (scene.render.transparency == Transparency::OpacityOptimization && scene.image.tilesX > 0) {
        // One optimisation over the whole image's fragments, blended into the next frame's. Its
        // image.samples are its own (gl/opacity_renderer.h): one solve, every sample blended.
        SpecReader im(doc.contains("image") ? doc["image"] : json::object(), file, "image", &overridden);
        im.fail("tiles",
                "render.transparency \"opacity_optimization\" renders the whole image at once (one "
                "optimisation over all its fragments); remove image.tiles");
    }
    if (scene.output.video && !scene.output.png) {
        SpecReader o(doc["output"], file, "output", &overridden);
        o.fail("video", "the movie is encoded from the PNG frames: add \"png\" to output.formats");
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
            if (text[i] == '\n') {
                ++line;
                column = 1;
            } else
                ++column;
        }
        std::string what = e.what();
        auto colon = what.find("syntax error");
        throw InputError(path + ":" + std::to_string(line) + ":" + std::to_string(column) +
                         ": invalid JSON: " + (colon != std::string::npos ? what.substr(colon) : what));
    }
    return parseScene(doc, path, overrides);
}

}  // namespace tc
