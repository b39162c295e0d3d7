// tubecast scene DATASET: prints the default scene of a dataset given alone (core/default_scene.h),
// the scene `tubecast render DATASET` renders, as a start for editing:
//     tubecast scene fibers.trk > fibers.json
#include <iostream>

#include "cli/commands.h"
#include "cli/scene_input.h"
#include "core/error.h"

namespace tc::cli {

void addSceneCommand(CLI::App& app) {
    auto path = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("scene", "Print the default scene of a dataset (what `render DATASET` renders)");
    cmd->add_option("dataset", *path, "Dataset file (.trk, .tck, .vtp, .pdb, ...)")->required();
    cmd->callback([path] {
        if (!isDatasetFile(*path))
            throw InputError(*path + ": not a dataset file (expected a line, particle or VTK format; docs/formats.md)");
        DatasetLoad load;
        std::cout << defaultSceneJson(*path, load).dump(2) << "\n";
    });
}

}  // namespace tc::cli
