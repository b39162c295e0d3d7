// tubecast convert IN OUT.vtp|OUT.tcb: writes a dataset (lines; particles as .vtp point clouds) (a file, or the dataset
// of a scene file, e.g. a generated tornado) as VTK XML polydata, so other tools (ParaView, the VTK benchmark in
// scripts/bench/) see exactly the lines tubecast renders, or as .tcb (docs/formats.md) for fast
// reloads.
#include <iostream>

#include "cli/commands.h"
#include "core/error.h"
#include "core/scene.h"
#include "io/dataset.h"
#include "io/line_formats.h"
#include "io/line_reader.h"
#include "io/partition.h"

namespace tc::cli {

void addConvertCommand(CLI::App& app) {
    struct Options {
        std::string in, out;
        std::vector<std::string> overrides;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("convert", "Write a dataset (or a scene's dataset) as .vtp or .tcb");
    cmd->add_option("input", options->in,
                    "Dataset file, a partitioned set (its directory or index.json), or a scene .json whose dataset to "
                    "write")
        ->required();
    cmd->add_option("output", options->out, "Output .vtp (VTK XML polydata) or .tcb (tubecast binary) file")
        ->required();
    cmd->add_option("--set", options->overrides, "Override a scene key (scene input only)");
    cmd->callback([options] {
        const bool tcb = options->out.ends_with(".tcb");
        if (!options->out.ends_with(".vtp") && !tcb)
            throw InputError(options->out + ": output must end in .vtp (VTK XML polydata) or .tcb (tubecast binary)");
        DatasetSpec spec;
        // A partitioned set's index.json is data (read whole), not a scene.
        if (options->in.ends_with(".json") && !isPartitionPath(options->in))
            spec = loadScene(options->in, options->overrides).dataset;
        else
            spec.path = options->in;
        DatasetLoad data = loadDataset(spec);
        if (data.isParticles()) {
            if (tcb) throw InputError(options->out + ": .tcb holds lines; write particles as .vtp");
            // A time series: the first frame, or the one dataset.frame pins.
            const ParticleSet& frame = data.particles.frames[data.particles.dataFrameFor(0, spec.frame)];
            writeParticleSetVtp(frame, options->out);
            std::cerr << "tubecast: wrote " << options->out << " (" << frame.size() << " particles)\n";
            return;
        }
        if (tcb) {
            writeTcb(data.lines, options->out);
        } else {
            writeLineSetVtp(data.lines, options->out);
        }
        std::cerr << "tubecast: wrote " << options->out << " (" << data.lines.polylineCount() << " polylines, "
                  << data.lines.segmentCount() << " segments)\n";
    });
}

}  // namespace tc::cli
