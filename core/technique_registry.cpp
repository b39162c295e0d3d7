#include "core/technique_registry.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"

namespace tc {
namespace {

std::string quoted(const std::string& s) {
    return "\"" + s + "\"";
}

// "a", "a" or "b", "a", "b" or "c"
std::string orList(const std::vector<std::string>& items) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (i) out += i + 1 == items.size() ? " or " : ", ";
        out += quoted(items[i]);
    }
    return out;
}

std::string sceneName(const Scene& scene) {
    return scene.file.empty() ? std::string("scene") : scene.file;
}

template <class T>
bool contains(const std::vector<T>& v, const T& x) {
    return std::find(v.begin(), v.end(), x) != v.end();
}

}  // namespace

const char* dataKindName(DataKind kind) {
    return kind == DataKind::Lines ? "lines" : "particles";
}

const char* transparencyName(Transparency t) {
    switch (t) {
        case Transparency::Opaque:
            return "opaque";
        case Transparency::ObjectOrder:
            return "object_order";
        case Transparency::KBuffer:
            return "kbuffer";
        case Transparency::DepthPeeling:
            return "depth_peeling";
        case Transparency::OpacityOptimization:
            return "opacity_optimization";
        case Transparency::Auto:
            return "auto";
    }
    return "?";
}

const char* aoMethodName(AoSpec::Method m) {
    return m == AoSpec::Method::RayTraced ? "ray_traced" : "cone_traced";
}

bool TechniqueDescriptor::takes(DataKind kind) const {
    return contains(data, kind);
}

PixelBuffers TechniqueDescriptor::pixelBuffersFor(const Scene& scene, DataKind kind) const {
    if (!pixelBuffers) return {0, 0, name};
    return pixelBuffers(scene, kind);
}

std::optional<SpecProblem> checkTechnique(const TechniqueDescriptor& d, const Scene& scene, DataKind kind) {
    const std::string technique = "technique " + quoted(d.name);
    if (!d.takes(kind)) {
        std::vector<std::string> kinds;
        for (DataKind k : d.data) kinds.push_back(dataKindName(k));
        return SpecProblem{"render.technique",
                           quoted(d.name) + " renders " + orList(kinds) + ", the dataset holds " + dataKindName(kind)};
    }
    const RenderSpec& r = scene.render;
    if (r.transparency != Transparency::Auto && !contains(d.transparency, r.transparency)) {
        std::vector<std::string> modes;
        for (Transparency t : d.transparency) modes.push_back(transparencyName(t));
        return SpecProblem{"render.transparency",
                           technique + " takes " + orList(modes) + ", got " + quoted(transparencyName(r.transparency))};
    }
    if (r.ao.enabled && !contains(d.ao, r.ao.method)) {
        if (d.ao.empty()) return SpecProblem{"render.ao", technique + " has no ambient occlusion"};
        std::vector<std::string> methods;
        for (AoSpec::Method m : d.ao) methods.push_back(aoMethodName(m));
        return SpecProblem{"render.ao.method", technique + " takes " + orList(methods) + " ambient occlusion, got " +
                                                   quoted(aoMethodName(r.ao.method))};
    }
    if (scene.style.halo.enabled) {
        // A ring around a tube: a line style, whatever technique draws the dataset.
        if (kind != DataKind::Lines)
            return SpecProblem{"style.halo",
                               std::string("halos are drawn around lines, the dataset holds ") + dataKindName(kind)};
        if (d.halo.empty()) return SpecProblem{"style.halo", technique + " draws no halos"};
        if (r.transparency != Transparency::Auto && !contains(d.halo, r.transparency)) {
            std::vector<std::string> modes;
            for (Transparency t : d.halo) modes.push_back(transparencyName(t));
            return SpecProblem{"style.halo", technique + " draws halos with render.transparency " + orList(modes) +
                                                 ", got " + quoted(transparencyName(r.transparency))};
        }
    }
    if (d.check) return d.check(scene, kind);
    return std::nullopt;
}

void requireTechnique(const TechniqueDescriptor& d, const Scene& scene, DataKind kind) {
    if (auto problem = checkTechnique(d, scene, kind))
        throw InputError(sceneName(scene) + ": " + problem->key + ": " + problem->message);
}

void refuseRegion(const Scene& scene, const std::string& key, const std::string& what, const std::string& supported) {
    throw InputError(sceneName(scene) + ": " + key + ": " + what +
                     " does not support data-parallel rendering (--mpi); supported: " + supported);
}

std::string TechniqueRegistry::regionSupport() const {
    std::string out;
    for (const TechniqueDescriptor& d : m_entries) {
        if (d.regionTransparency.empty()) continue;
        out += (out.empty() ? "" : ", ") + d.name + " (";
        for (std::size_t i = 0; i < d.regionTransparency.size(); ++i)
            out += (i ? ", " : "") + std::string(transparencyName(d.regionTransparency[i]));
        out += ")";
    }
    return out.empty() ? "none" : out;
}

void TechniqueRegistry::requireRegions(const Scene& scene) const {
    if (scene.render.technique.isAuto()) return;
    const std::string name = scene.render.technique.name();
    const TechniqueDescriptor* d = find(name);
    if (!d || d->regionTransparency.empty())
        refuseRegion(scene, "render.technique", "\"" + name + "\"", regionSupport());
    const std::vector<Transparency>& modes = d->regionTransparency;
    if (scene.render.transparency == Transparency::Auto) return;  // checked again once resolved
    if (std::find(modes.begin(), modes.end(), scene.render.transparency) == modes.end())
        refuseRegion(scene, "render.transparency",
                     "\"" + name + "\" with \"" + transparencyName(scene.render.transparency) + "\"", regionSupport());
}

bool isSoftwareRasterizer(const std::string& glRenderer) {
    std::string lower = glRenderer;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    for (const char* software : {"llvmpipe", "softpipe", "swrast"})
        if (lower.find(software) != std::string::npos) return true;
    return false;
}

TransparencyChoice resolveTransparency(const TechniqueDescriptor& d, bool translucent, bool halo) {
    const bool opaqueDrawsHalo = contains(d.halo, Transparency::Opaque);
    if (!translucent && halo && !opaqueDrawsHalo && contains(d.halo, d.exactTransparency))
        return {d.exactTransparency, std::string("render.transparency auto: ") + transparencyName(d.exactTransparency) +
                                         " (every opacity is 1, but the opaque mode of " + d.name +
                                         " draws no halos (style.halo); with opacity 1 the exact-order mode gives "
                                         "the opaque image with halos)"};
    if (!translucent) return {Transparency::Opaque, "render.transparency auto: opaque (every opacity is 1)"};
    return {d.exactTransparency, std::string("render.transparency auto: ") + transparencyName(d.exactTransparency) +
                                     " (opacity below 1; the exact-order transparent mode of " + d.name + ")"};
}

void TechniqueRegistry::add(TechniqueDescriptor d) {
    if (d.name.empty() || d.name == "auto" || find(d.name) || !d.create)
        throw Error(ExitCode::Internal, "technique registry: bad or duplicate entry \"" + d.name + "\"");
    m_entries.push_back(std::move(d));
}

const TechniqueDescriptor* TechniqueRegistry::find(const std::string& name) const {
    for (const TechniqueDescriptor& d : m_entries)
        if (d.name == name) return &d;
    return nullptr;
}

const TechniqueDescriptor& TechniqueRegistry::validate(const Scene& scene, DataKind kind) const {
    const TechniqueDescriptor* d = find(scene.render.technique.name());
    if (!d) {
        std::vector<std::string> names{"auto"};
        for (const TechniqueDescriptor& e : m_entries) names.push_back(e.name);
        std::string list;
        for (const std::string& n : names) list += (list.empty() ? "" : ", ") + quoted(n);
        throw InputError(sceneName(scene) + ": render.technique: expected one of " + list + ", got " +
                         quoted(scene.render.technique.name()));
    }
    requireTechnique(*d, scene, kind);
    return *d;
}

void TechniqueRegistry::validateWithoutData(const Scene& scene) const {
    if (scene.render.technique.isAuto()) {
        std::optional<SpecProblem> first;
        for (const TechniqueDescriptor& d : m_entries)
            for (DataKind kind : d.data) {
                auto problem = checkTechnique(d, scene, kind);
                if (!problem) return;
                if (!first) first = problem;
            }
        if (first)
            throw InputError(sceneName(scene) + ": " + first->key + ": no technique takes this (" + first->message +
                             ")");
        return;
    }
    const TechniqueDescriptor* d = find(scene.render.technique.name());
    if (!d) validate(scene, DataKind::Lines);  // throws the unknown-name error
    std::optional<SpecProblem> first;
    for (DataKind kind : d->data) {
        auto problem = checkTechnique(*d, scene, kind);
        if (!problem) return;
        if (!first) first = problem;
    }
    if (first) throw InputError(sceneName(scene) + ": " + first->key + ": " + first->message);
}

TechniqueRegistry::AutoChoice TechniqueRegistry::resolveAuto(const Scene& scene, DataKind kind,
                                                             const std::string& glRenderer) const {
    const bool software = isSoftwareRasterizer(glRenderer);
    const TechniqueBackend preferred = software ? TechniqueBackend::Cpu : TechniqueBackend::Gl;
    const std::string gl = "GL renderer " + quoted(glRenderer) + (software ? " is a software rasterizer" : "");
    // Why the preferred backend's candidates were passed over, for the log line.
    std::vector<std::string> passedOver;
    for (int round = 0; round < 2; ++round) {
        const bool wantPreferred = round == 0;
        for (const TechniqueDescriptor& d : m_entries) {
            if ((d.backend == preferred) != wantPreferred || !contains(d.autoData, kind)) continue;
            if (auto problem = checkTechnique(d, scene, kind)) {
                if (wantPreferred) passedOver.push_back(problem->message + " (" + problem->key + ")");
                continue;
            }
            if (contains(d.transparencyAliases, scene.render.transparency)) {
                if (wantPreferred)
                    passedOver.push_back(d.name + " renders render.transparency " +
                                         quoted(transparencyName(scene.render.transparency)) + " as exact compositing");
                continue;
            }
            std::string why = "render.technique auto: " + d.name + " (" + gl;
            for (const std::string& p : passedOver) why += "; " + p;
            return {&d, why + ")"};
        }
    }
    std::string reasons;
    for (const TechniqueDescriptor& d : m_entries)
        if (contains(d.autoData, kind))
            if (auto problem = checkTechnique(d, scene, kind))
                reasons += (reasons.empty() ? "" : "; ") + problem->key + ": " + problem->message;
    throw InputError(sceneName(scene) + ": render.technique: \"auto\" finds no technique for " + dataKindName(kind) +
                     " with these settings (" + reasons + ")");
}

}  // namespace tc
