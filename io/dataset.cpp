#include "io/dataset.h"

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "core/error.h"
#include "core/generators.h"
#include "core/particle_generators.h"
#include "io/line_formats.h"
#include "io/line_reader.h"
#include "io/particle_reader.h"
#include "io/partition.h"
#include "io/stream_tracer.h"

namespace tc {

DatasetLoad loadDataset(const DatasetSpec& spec) {
    auto start = std::chrono::steady_clock::now();
    DatasetLoad load;
    if (spec.generate == "droplets") {
        load.particles.frames.push_back(generateDroplets(spec.particles, spec.seed));
        load.source = "generate:droplets(particles=" + std::to_string(spec.particles) +
                      ",seed=" + std::to_string(spec.seed) + ")";
    } else if (isParticleFile(spec.path)) {
        load.particles = readParticles(spec.path);
        load.source = spec.path;
    } else if (!spec.generate.empty()) {
        load.lines = generateDataset(spec.generate, spec.lines, spec.points, spec.seed);
        load.source = "generate:" + spec.generate + "(lines=" + std::to_string(spec.lines) +
                      ",points=" + std::to_string(spec.points) + ",seed=" + std::to_string(spec.seed) + ")";
    } else if (spec.trace) {
        load.lines = traceStreamlines(spec.path, *spec.trace, &load.cleaned);
        load.source = spec.path + " (traced)";
    } else if (isPartitionPath(spec.path)) {  // the whole set: every brick, each segment once
        load.lines = readPartitionWhole(readPartitionIndex(spec.path));
        load.source = spec.path;
    } else if (isVtkFile(spec.path)) {
        VtkFileData data = readVtkFile(spec.path, &load.cleaned);  // lines, or points as particles
        if (data.isPoints)
            load.particles.frames.push_back(std::move(data.points));
        else
            load.lines = std::move(data.lines);
        load.source = spec.path;
    } else {
        load.lines = readLineSet(spec.path, &load.cleaned);
        load.source = spec.path;
    }
    // Empty is valid (the frames show the background, with a warning: cli/render.cpp); emptied by
    // cleaning is not.
    if (!load.isParticles() && load.lines.polylineCount() == 0 && load.cleaned.removed())
        throw InputError(load.source + ": no polylines to render (" + load.cleaned.summary() + ")");
    load.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return load;
}

bool isDatasetFile(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return (ext != ".json" && (isNativeLineFormat(ext) || isVtkFile(path) || isParticleFile(path))) ||
           isPartitionPath(path);
}

}  // namespace tc
