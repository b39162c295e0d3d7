// tubecast merge-timings OUT IN...: the per-shard timings files of a batch as one CSV.
#include <filesystem>
#include <memory>

#include "cli/batch.h"
#include "cli/commands.h"
#include "core/error.h"

namespace tc::cli {

void addMergeTimingsCommand(CLI::App& app) {
    struct Options {
        std::string out;
        std::vector<std::string> inputs;
        bool overwrite = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "merge-timings", "Concatenate timings CSVs of several shards (timings.I-of-N.csv) into one, one header");
    cmd->add_option("out", o->out, "Merged CSV to write")->required();
    cmd->add_option("inputs", o->inputs, "Timings CSVs, in the order to concatenate")->required();
    cmd->add_flag("--overwrite", o->overwrite, "Replace OUT if it exists");
    cmd->callback([o] {
        std::error_code ec;
        if (std::filesystem::exists(o->out, ec) && !o->overwrite)
            throw OutputError(o->out + " exists; use --overwrite to replace it");
        for (const auto& in : o->inputs)
            if (std::filesystem::equivalent(in, o->out, ec)) throw InputError(in + ": is also the output");
        mergeTimings(o->out, o->inputs);
    });
}

}  // namespace tc::cli
