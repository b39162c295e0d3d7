#include "cli/scene_input.h"

#include <filesystem>

#include "core/default_scene.h"
#include "core/error.h"

namespace tc::cli {

nlohmann::json defaultSceneJson(const std::string& path, DatasetLoad& load) {
    if (!std::filesystem::exists(path)) throw InputError(path + ": no such file");
    DatasetSpec spec;
    spec.path = path;
    load = loadDataset(spec);
    return defaultSceneFor(path, load.isParticles() ? nullptr : &load.lines,
                           load.isParticles() ? &load.particles : nullptr);
}

SceneInput loadSceneInput(const std::string& path, const std::vector<std::string>& overrides) {
    SceneInput in;
    if (!isDatasetFile(path)) {
        in.scene = loadScene(path, overrides);
        return in;
    }
    DatasetLoad load;
    const nlohmann::json doc = defaultSceneJson(path, load);
    // Parsed without a file, so dataset.path stays as given (relative to the working directory);
    // messages then name the dataset.
    in.scene = parseScene(doc, "", overrides);
    in.scene.file = path;
    in.data = std::move(load);
    return in;
}

}  // namespace tc::cli
