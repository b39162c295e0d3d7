// tubecast techniques [--json | --markdown]: the technique registry as a user reads it: each
// technique's name (the render.technique value), the data it renders, its transparency modes and
// ambient occlusion methods, the modes that draw style.halo, where it runs and the paper it
// implements. README.md's table is the
// --markdown output (a test compares them).
#include <iostream>
#include <sstream>

#include "cli/commands.h"
#include "cli/technique_registry.h"

namespace tc::cli {
namespace {

template <class T, class Name>
std::string joined(const std::vector<T>& items, Name name, const std::string& separator) {
    std::string out;
    for (const T& item : items) out += (out.empty() ? "" : separator) + std::string(name(item));
    return out;
}

std::string dataOf(const TechniqueDescriptor& d, const std::string& separator) {
    return joined(d.data, dataKindName, separator);
}
std::string transparencyOf(const TechniqueDescriptor& d, const std::string& separator) {
    return joined(d.transparency, transparencyName, separator);
}
std::string aoOf(const TechniqueDescriptor& d, const std::string& separator) {
    return d.ao.empty() ? std::string("none") : joined(d.ao, aoMethodName, separator);
}
std::string regionsOf(const TechniqueDescriptor& d, const std::string& separator) {
    return d.regionTransparency.empty() ? std::string("none")
                                        : joined(d.regionTransparency, transparencyName, separator);
}
std::string halosOf(const TechniqueDescriptor& d, const std::string& separator) {
    return d.halo.empty() ? std::string("none") : joined(d.halo, transparencyName, separator);
}
const char* backendOf(const TechniqueDescriptor& d) {
    return d.backend == TechniqueBackend::Gl ? "GL" : "CPU";
}

nlohmann::json asJson(const TechniqueRegistry& registry) {
    nlohmann::json list = nlohmann::json::array();
    for (const TechniqueDescriptor& d : registry.all()) {
        nlohmann::json e;
        e["name"] = d.name;
        e["summary"] = d.summary;
        e["paper"] = d.paper;
        e["backend"] = d.backend == TechniqueBackend::Gl ? "gl" : "cpu";
        for (DataKind k : d.data) e["data"].push_back(dataKindName(k));
        for (DataKind k : d.autoData) e["auto_for"].push_back(dataKindName(k));
        if (d.autoData.empty()) e["auto_for"] = nlohmann::json::array();
        for (Transparency t : d.transparency) e["transparency"].push_back(transparencyName(t));
        e["exact_transparency"] = transparencyName(d.exactTransparency);
        e["ao"] = nlohmann::json::array();
        for (AoSpec::Method m : d.ao) e["ao"].push_back(aoMethodName(m));
        e["mpi"] = nlohmann::json::array();  // transparency modes for `render --mpi`
        for (Transparency t : d.regionTransparency) e["mpi"].push_back(transparencyName(t));
        e["halo"] = nlohmann::json::array();  // transparency modes that draw style.halo
        for (Transparency t : d.halo) e["halo"].push_back(transparencyName(t));
        list.push_back(e);
    }
    return list;
}

}  // namespace

std::string techniquesMarkdown(const TechniqueRegistry& registry) {
    std::ostringstream out;
    out << "| technique | data | render.transparency | render.ao.method | runs on | implements |\n"
        << "|---|---|---|---|---|---|\n";
    for (const TechniqueDescriptor& d : registry.all())
        out << "| `" << d.name << "` | " << dataOf(d, ", ") << " | " << transparencyOf(d, ", ") << " | "
            << aoOf(d, ", ") << " | " << backendOf(d) << " | " << d.paper << " |\n";
    return out.str();
}

void addTechniquesCommand(CLI::App& app) {
    auto format = std::make_shared<std::string>("text");
    CLI::App* cmd =
        app.add_subcommand("techniques", "List the render techniques (render.technique) and what each takes");
    cmd->add_flag_callback(
        "--json", [format] { *format = "json"; }, "As JSON");
    cmd->add_flag_callback(
        "--markdown", [format] { *format = "markdown"; }, "As a Markdown table (README.md's)");
    cmd->callback([format] {
        const TechniqueRegistry& registry = techniqueRegistry();
        if (*format == "json") {
            std::cout << asJson(registry).dump(2) << "\n";
            return;
        }
        if (*format == "markdown") {
            std::cout << techniquesMarkdown(registry);
            return;
        }
        for (const TechniqueDescriptor& d : registry.all()) {
            std::cout << d.name << " (" << backendOf(d) << ")\n"
                      << "  " << d.summary << "\n"
                      << "  data:         " << dataOf(d, ", ") << "\n"
                      << "  transparency: " << transparencyOf(d, ", ") << "\n"
                      << "  ao:           " << aoOf(d, ", ") << "\n"
                      << "  --mpi:        " << regionsOf(d, ", ") << "\n"
                      << "  style.halo:   " << halosOf(d, ", ") << "\n"
                      << "  implements:   " << d.paper << "\n";
        }
        std::cout
            << "render.technique \"auto\": on a software GL rasterizer (llvmpipe, softpipe, swrast) the first CPU "
               "technique that takes the scene, else the first GL one (voxel_raycast only when named)\n";
    });
}

}  // namespace tc::cli
