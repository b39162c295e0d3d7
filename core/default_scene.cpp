#include "core/default_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace tc {
namespace {

// The first attribute in the file's order that is a scalar: vector components (NAME_x, _y, _z)
// are skipped, their NAME_magnitude is a scalar; attributes without a finite value are skipped.
const Attribute* firstScalar(const std::vector<Attribute>& attributes) {
    for (const Attribute& a : attributes) {
        const std::string& n = a.name;
        const bool component =
            n.size() > 2 && n[n.size() - 2] == '_' && (n.back() == 'x' || n.back() == 'y' || n.back() == 'z');
        if (!component && !std::isnan(a.min)) return &a;
    }
    return nullptr;
}

nlohmann::json colorBy(const Attribute& a) {
    return {{"attribute", a.name}, {"colormap", "viridis"}, {"range", "auto"}};
}

std::string lowerExtension(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

// Half the spacing of `count` particles spread evenly over the bounding box's non-flat axes.
float halfSpacing(const Bounds& b, std::size_t count) {
    const glm::vec3 e = b.extent();
    const float diagonal = glm::length(e);
    if (!(diagonal > 0.0f) || count == 0) return 0.5f;
    double measure = 1.0;
    int dims = 0;
    for (int i = 0; i < 3; ++i)
        if (e[i] > 1e-6f * diagonal) measure *= e[i], ++dims;
    if (dims == 0) return 0.5f * diagonal;
    return float(0.5 * std::pow(measure / double(count), 1.0 / dims));
}

}  // namespace

nlohmann::json defaultSceneFor(const std::string& path, const LineSet* lines, const ParticleData* particles) {
    nlohmann::json scene;
    scene["description"] = "The default scene of " + std::filesystem::path(path).filename().string() +
                           " (tubecast scene): edit it, then `tubecast render` it";
    scene["dataset"] = {{"path", path}};
    nlohmann::json style = nlohmann::json::object();
    if (lines) {
        // No extent (no vertices, or all at one point), no scale: the style's default radius stands.
        const float diagonal = lines->bounds.empty() ? 0.0f : glm::length(lines->bounds.extent());
        if (diagonal > 0.0f) style["radius"] = kDefaultLineRadiusFraction * diagonal;
        const std::string ext = lowerExtension(path);
        if (ext == ".trk" || ext == ".tck")
            style["color"] = "direction";
        else if (const Attribute* a = firstScalar(lines->attributes))
            style["color"] = colorBy(*a);
    } else if (particles && !particles->frames.empty()) {
        const ParticleSet& first = particles->frames.front();
        if (first.radii.empty()) style["radius"] = halfSpacing(particles->bounds(), particles->maxParticles());
        if (first.colors.empty())
            if (const Attribute* a = firstScalar(first.attributes)) style["color"] = colorBy(*a);
        if (particles->frameCount() > 1) {
            // Every data frame, seen from the fitted camera (an orbit through 0 degrees).
            scene["animation"] = {{"type", "orbit"}, {"frames", particles->frameCount()}, {"degrees", 0}};
            scene["output"] = {{"name", "frame.####"}};
        }
    }
    if (!style.empty()) scene["style"] = style;
    if (!scene.contains("output")) scene["output"] = {{"name", std::filesystem::path(path).stem().string()}};
    return scene;
}

}  // namespace tc
