// tubecast partition DATA -n N -o DIR: decomposes a line set once into N k-d regions and writes
// one brick per region plus index.json (io/partition.h), so that each rank of a data-parallel
// render reads only its brick. DATA is a dataset file or a scene (its dataset), as for convert.
#include "io/partition.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "cli/commands.h"
#include "core/default_scene.h"
#include "core/derived_attributes.h"
#include "core/error.h"
#include "core/kd_decomposition.h"
#include "core/scene.h"
#include "io/atomic_file.h"
#include "io/dataset.h"

namespace tc::cli {

namespace fs = std::filesystem;

namespace {

// The largest radius a scene's style gives a line vertex: the constant, or the top of the
// attribute mapping (NaN values map to radius_range[0]).
float sceneMaxRadius(const StyleSpec& style) {
    if (style.radius.attribute.empty()) return style.radius.constant;
    return std::max(style.radius.radiusLo, style.radius.radiusHi);
}

}  // namespace

void addPartitionCommand(CLI::App& app) {
    struct Options {
        std::string in, out;
        int regions = 0;
        float radius = 0;
        std::vector<std::string> overrides;
        bool overwrite = false;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "partition", "Decompose a line set into N k-d regions: DIR/region-K.tcb bricks and DIR/index.json");
    cmd->add_option("input", options->in, "Dataset file, or a scene .json whose dataset to partition")->required();
    cmd->add_option("-n,--regions", options->regions, "Number of regions (>= 1; any integer)")
        ->required()
        ->check(CLI::Range(1, 1 << 20));
    cmd->add_option("-o,--output", options->out, "Output directory")->required();
    cmd->add_option("--radius", options->radius,
                    "Largest tube radius the bricks must hold (default: the scene's largest radius, or the "
                    "default radius of a dataset alone)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--set", options->overrides, "Override a scene key (scene input only)");
    cmd->add_flag("--overwrite", options->overwrite, "Replace an existing partition in the output directory");
    cmd->callback([options] {
        const bool scene = options->in.ends_with(".json") && !isPartitionPath(options->in);
        if (!scene && !options->overrides.empty())
            throw InputError("--set: only a scene input has keys to override (" + options->in + " is a dataset)");
        Scene spec;
        if (scene)
            spec = loadScene(options->in, options->overrides);
        else
            spec.dataset.path = options->in;
        DatasetLoad data = loadDataset(spec.dataset);
        if (data.isParticles())
            throw InputError(data.source +
                             ": particle data: partitioned sets hold lines only (.tcb bricks); particles are "
                             "decomposed in memory when rendered");
        LineSet& lines = data.lines;
        // Attributes derived from whole polylines or all the data (arc_length, line_length,
        // local_density) cannot be derived again from a brick's cut runs: a scene's style gets
        // the ones it names stored in the bricks.
        if (scene) {
            std::vector<std::string> derived;
            for (const std::string* name :
                 {&spec.style.radius.attribute, &spec.style.color.attribute, &spec.style.opacity.attribute})
                if (isDerivedAttribute(*name) && !lines.attribute(*name)) derived.push_back(*name);
            try {
                addDerivedAttributes(lines, derived);
            } catch (const InputError& e) {
                throw InputError(options->in + ": style: " + e.what());
            }
        }
        if (!std::isfinite(options->radius))
            throw InputError("--radius: expected a finite radius > 0, got " + std::to_string(options->radius));
        float radius = options->radius;  // 0: not given
        if (radius == 0 && scene) radius = sceneMaxRadius(spec.style);
        // The default scene's radius (core/default_scene.h); no lines, nothing to assign.
        if (radius == 0 && !lines.bounds.empty())
            radius = kDefaultLineRadiusFraction * glm::length(lines.bounds.extent());

        ensureWritableDir(options->out);
        if (!options->overwrite) {
            std::vector<std::string> names{"index.json"};
            for (int k = 0; k < options->regions; ++k) {
                names.push_back("region-" + std::to_string(k) + ".tcb");
                names.push_back("region-" + std::to_string(k) + ".runs");
            }
            for (const std::string& name : names)
                if (fs::exists(fs::path(options->out) / name))
                    throw OutputError((fs::path(options->out) / name).string() +
                                      ": exists (use --overwrite to replace the partition)");
        }
        const KdDecomposition tree = KdDecomposition::build(segmentMidpoints(lines), options->regions);
        const PartitionIndex index = writePartition(lines, tree, radius, data.source, options->out);

        std::uint64_t assigned = 0, stored = 0;
        for (const PartitionBrick& b : index.bricks) {
            assigned += b.assignedSegments;
            stored += b.segments;
        }
        const double perSegment = index.segments ? double(assigned) / double(index.segments) : 0.0;
        std::cerr << "tubecast: wrote " << index.path << " and " << index.regionCount() << " bricks (" << index.segments
                  << " segments in " << index.polylines << " polylines; " << assigned << " assigned, " << std::fixed
                  << std::setprecision(3) << perSegment << " per segment; " << stored
                  << " stored with joint neighbours; tube radius " << std::defaultfloat << radius << ")\n";
    });
}

}  // namespace tc::cli
