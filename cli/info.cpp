// tubecast info DATASET|SCENE [--json]: counts, bounds, attribute ranges and memory estimate of a
// dataset, or of a scene's dataset with the derived attributes its style asks for.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/particle_info.h"
#include "core/derived_attributes.h"
#include "core/error.h"
#include "core/scene.h"
#include "io/dataset.h"
#include "io/line_reader.h"
#include "io/paraview_preset.h"
#include "io/particle_reader.h"
#include "io/partition.h"

namespace tc::cli {

namespace fs = std::filesystem;

void addInfoCommand(CLI::App& app) {
    struct Options {
        std::string path;
        bool json = false;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("info", "Print counts, bounds and attributes of a dataset");
    cmd->add_option("dataset", options->path, "Dataset file (.vtk, .vtp, ...) or scene file (.json)")->required();
    cmd->add_flag("--json", options->json, "Print JSON instead of text");
    cmd->callback([options] {
        if (isParticleFile(options->path)) {  // particles: cli/particle_info.cpp
            printParticleInfo(options->path, options->json);
            return;
        }
        // A scene: its dataset (file, generator or dataset.trace) plus the derived attributes
        // its style names, i.e. exactly what `render` would style.
        const bool isPartition = isPartitionPath(options->path);  // read whole, as render reads it
        const bool isScene = fs::path(options->path).extension() == ".json" && !isPartition;
        CleanReport cleaned;
        LineSet lines;
        std::vector<std::string> derived;
        if (isScene) {
            Scene scene = loadScene(options->path);
            loadStylePresets(scene.style, scene.file);
            if (!scene.dataset.path.empty() && isParticleFile(scene.dataset.path)) {
                printParticleInfo(scene.dataset.path, options->json);
                return;
            }
            DatasetLoad data = loadDataset(scene.dataset);
            if (data.isParticles()) {  // a generator or a VTK point cloud
                printParticleInfo(data.particles, data.source, options->json);
                return;
            }
            lines = std::move(data.lines);
            cleaned = data.cleaned;
            for (const std::string* name :
                 {&scene.style.radius.attribute, &scene.style.color.attribute, &scene.style.opacity.attribute})
                if (isDerivedAttribute(*name) && !lines.attribute(*name)) derived.push_back(*name);
            try {
                addDerivedAttributes(lines, derived);
            } catch (const InputError& e) {
                throw InputError(options->path + ": style: " + e.what());
            }
        } else if (isVtkFile(options->path)) {
            VtkFileData data = readVtkFile(options->path, &cleaned);
            if (data.isPoints) {
                printParticleInfo(ParticleData{{std::move(data.points)}}, options->path, options->json);
                return;
            }
            lines = std::move(data.lines);
        } else if (isPartition) {
            lines = readPartitionWhole(readPartitionIndex(options->path));
        } else {
            lines = readLineSet(options->path, &cleaned);
        }
        // What the renderer uploads (gl/line_geometry.cpp): per vertex position+radius and colour
        // (vec4 each), polyline id and flags (uint32 each); per segment two uint32 vertex indices
        // and, on the default compute billboard path, two vec4 corners. Per-pixel buffers depend
        // on the image and transparency mode and are checked against render.memory_budget_mb.
        const std::uint64_t vertexBytes = std::uint64_t(lines.vertexCount()) * (16 + 16 + 4 + 4);
        const std::uint64_t segmentBytes = std::uint64_t(lines.segmentCount()) * 8;
        const std::uint64_t billboardBytes = std::uint64_t(lines.segmentCount()) * 32;
        const std::uint64_t gpuBytes = vertexBytes + segmentBytes + billboardBytes;
        std::uint64_t hostBytes = std::uint64_t(lines.vertexCount()) * 12 + std::uint64_t(lines.offsets.size()) * 4;
        for (const auto& a : lines.attributes) hostBytes += std::uint64_t(a.values.size()) * 4;

        nlohmann::json j;
        j["file"] = options->path;
        j["polylines"] = lines.polylineCount();
        j["vertices"] = lines.vertexCount();
        j["segments"] = lines.segmentCount();
        j["bounds"] = {{"min", {lines.bounds.lo.x, lines.bounds.lo.y, lines.bounds.lo.z}},
                       {"max", {lines.bounds.hi.x, lines.bounds.hi.y, lines.bounds.hi.z}}};
        j["attributes"] = nlohmann::json::array();
        for (const auto& a : lines.attributes) {
            bool isDerived = std::find(derived.begin(), derived.end(), a.name) != derived.end();
            // JSON has no NaN: an attribute without finite values has null bounds.
            auto number = [](float v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
            j["attributes"].push_back(
                {{"name", a.name}, {"min", number(a.min)}, {"max", number(a.max)}, {"derived", isDerived}});
        }
        j["skipped"] = {{"non_finite_vertices", cleaned.nonFiniteVertices},
                        {"duplicate_vertices", cleaned.duplicateVertices},
                        {"dropped_polylines", cleaned.droppedPolylines}};
        j["gpu_buffers_bytes"] = {
            {"vertices", vertexBytes}, {"segments", segmentBytes}, {"billboards", billboardBytes}, {"total", gpuBytes}};
        j["gpu_memory_mb"] = double(gpuBytes) / (1024.0 * 1024.0);
        j["host_memory_bytes"] = hostBytes;
        if (options->json) {
            std::cout << j.dump(2) << "\n";
            return;
        }
        std::cout << options->path << "\n"
                  << "  polylines " << lines.polylineCount() << ", vertices " << lines.vertexCount() << ", segments "
                  << lines.segmentCount() << "\n"
                  << "  bounds [" << lines.bounds.lo.x << ", " << lines.bounds.lo.y << ", " << lines.bounds.lo.z
                  << "] .. [" << lines.bounds.hi.x << ", " << lines.bounds.hi.y << ", " << lines.bounds.hi.z << "]\n";
        for (const auto& a : j["attributes"])
            std::cout << "  attribute " << std::left << std::setw(20) << a["name"].get<std::string>() << " ["
                      << a["min"].dump() << ", " << a["max"].dump() << "]"
                      << (a["derived"].get<bool>() ? " (derived)" : "") << "\n";
        if (cleaned.any()) std::cout << "  skipped: " << cleaned.summary() << "\n";
        std::cout << "  GPU buffers " << gpuBytes << " bytes (~" << std::fixed << std::setprecision(1)
                  << j["gpu_memory_mb"].get<double>() << " MB: vertices " << vertexBytes << ", segments "
                  << segmentBytes << ", billboards " << billboardBytes << ")\n";
    });
}

}  // namespace tc::cli
