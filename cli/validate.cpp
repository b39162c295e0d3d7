// tubecast validate SCENE: parse and check a scene (and that its dataset file exists) without
// rendering or touching the GPU.
#include <filesystem>
#include <iostream>

#include "cli/commands.h"
#include "cli/scene_input.h"
#include "cli/technique_registry.h"
#include "core/error.h"
#include "core/scene.h"
#include "io/paraview_preset.h"

namespace tc::cli {

void addValidateCommand(CLI::App& app) {
    struct Options {
        std::string scene;
        std::vector<std::string> overrides;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("validate", "Check a scene file: keys, types, ranges, dataset path");
    cmd->add_option("scene", options->scene, "Scene JSON file")->required();
    cmd->add_option("--set", options->overrides, "Override a scene key: key.path=value (repeatable)");
    cmd->callback([options] {
        Scene scene = loadSceneInput(options->scene, options->overrides).scene;
        loadStylePresets(scene.style, scene.file);
        techniqueRegistry().validateWithoutData(scene);
        if (!scene.dataset.path.empty() && !std::filesystem::exists(scene.dataset.path))
            throw InputError(options->scene + ": dataset.path: no such file: " + scene.dataset.path);
        std::cout << options->scene << ": ok (" << scene.frameCount() << " frame"
                  << (scene.frameCount() == 1 ? "" : "s") << ", " << scene.image.width << "x" << scene.image.height
                  << ")\n";
    });
}

}  // namespace tc::cli
