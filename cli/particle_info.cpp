#include "cli/particle_info.h"

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>

#include "io/particle_reader.h"

namespace tc::cli {

void printParticleInfo(const std::string& path, bool json) {
    printParticleInfo(readParticles(path), path, json);
}

void printParticleInfo(const ParticleData& data, const std::string& path, bool json) {
    const Bounds b = data.bounds();
    std::size_t total = 0;
    float rMin = std::numeric_limits<float>::infinity(), rMax = -rMin;
    for (const ParticleSet& f : data.frames) {
        total += f.size();
        for (float r : f.radii) rMin = std::min(rMin, r), rMax = std::max(rMax, r);
    }
    const ParticleSet& first = data.frames.front();
    nlohmann::json j;
    j["file"] = path;
    j["kind"] = "particles";
    j["frames"] = data.frameCount();
    j["particles_first_frame"] = first.size();
    j["particles_max"] = data.maxParticles();
    j["particles_total"] = total;
    j["bounds"] = {{"min", {b.lo.x, b.lo.y, b.lo.z}}, {"max", {b.hi.x, b.hi.y, b.hi.z}}};
    j["radii"] = first.radii.empty() ? nlohmann::json(nullptr) : nlohmann::json({{"min", rMin}, {"max", rMax}});
    j["colors"] = !first.colors.empty();
    j["attributes"] = nlohmann::json::array();
    for (const auto& a : first.attributes)
        j["attributes"].push_back({{"name", a.name}, {"min", a.min}, {"max", a.max}});
    // Sphere renderer memory per frame: centre+radius and colour (vec4 each), id, sort key and order.
    j["gpu_memory_mb"] = double(data.maxParticles()) * 44.0 / (1024.0 * 1024.0);
    if (json) {
        std::cout << j.dump(2) << "\n";
        return;
    }
    std::cout << path << "\n"
              << "  particles " << first.size() << " (first frame), frames " << data.frameCount() << ", max "
              << data.maxParticles() << " per frame\n"
              << "  bounds [" << b.lo.x << ", " << b.lo.y << ", " << b.lo.z << "] .. [" << b.hi.x << ", " << b.hi.y
              << ", " << b.hi.z << "]\n";
    if (!first.radii.empty()) std::cout << "  radii [" << rMin << ", " << rMax << "]\n";
    if (!first.colors.empty()) std::cout << "  per-particle colours\n";
    for (const auto& a : first.attributes)
        std::cout << "  attribute " << std::left << std::setw(20) << a.name << " [" << a.min << ", " << a.max << "]\n";
    std::cout << "  GPU memory ~" << std::fixed << std::setprecision(1) << j["gpu_memory_mb"].get<double>() << " MB\n";
}

}  // namespace tc::cli
