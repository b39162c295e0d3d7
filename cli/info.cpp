// tubecast info DATASET [--json]: counts, bounds and attribute ranges of a dataset.
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/error.h"
#include "io/line_reader.h"

namespace tc::cli {

void addInfoCommand(CLI::App& app) {
    struct Options {
        std::string path;
        bool json = false;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("info", "Print counts, bounds and attributes of a dataset");
    cmd->add_option("dataset", options->path, "Dataset file (.vtk, .vtp)")->required();
    cmd->add_flag("--json", options->json, "Print JSON instead of text");
    cmd->callback([options] {
        CleanReport cleaned;
        LineSet lines = readLineSet(options->path, &cleaned);
        nlohmann::json j;
        j["file"] = options->path;
        j["polylines"] = lines.polylineCount();
        j["vertices"] = lines.vertexCount();
        j["segments"] = lines.segmentCount();
        j["bounds"] = {{"min", {lines.bounds.lo.x, lines.bounds.lo.y, lines.bounds.lo.z}},
                       {"max", {lines.bounds.hi.x, lines.bounds.hi.y, lines.bounds.hi.z}}};
        j["attributes"] = nlohmann::json::array();
        for (const auto& a : lines.attributes)
            j["attributes"].push_back({{"name", a.name}, {"min", a.min}, {"max", a.max}});
        j["skipped"] = {{"non_finite_vertices", cleaned.nonFiniteVertices},
                        {"duplicate_vertices", cleaned.duplicateVertices},
                        {"dropped_polylines", cleaned.droppedPolylines}};
        // Renderer memory: position+radius and colour as vec4 per vertex, 2 indices per segment.
        j["gpu_memory_mb"] = double(lines.vertexCount() * 32 + lines.segmentCount() * 8) / (1024.0 * 1024.0);
        if (options->json) {
            std::cout << j.dump(2) << "\n";
            return;
        }
        std::cout << options->path << "\n"
                  << "  polylines " << lines.polylineCount() << ", vertices " << lines.vertexCount() << ", segments "
                  << lines.segmentCount() << "\n"
                  << "  bounds [" << lines.bounds.lo.x << ", " << lines.bounds.lo.y << ", " << lines.bounds.lo.z
                  << "] .. [" << lines.bounds.hi.x << ", " << lines.bounds.hi.y << ", " << lines.bounds.hi.z << "]\n";
        for (const auto& a : lines.attributes)
            std::cout << "  attribute " << std::left << std::setw(20) << a.name << " [" << a.min << ", " << a.max << "]\n";
        if (cleaned.any()) std::cout << "  skipped: " << cleaned.summary() << "\n";
        std::cout << "  GPU memory ~" << std::fixed << std::setprecision(1) << j["gpu_memory_mb"].get<double>() << " MB\n";
    });
}

}  // namespace tc::cli
