#pragma once
// A scene's dataset: read from a file (by extension) or made by a built-in generator.
#include <string>

#include "core/line_set.h"
#include "core/particle_set.h"
#include "core/scene.h"

namespace tc {

struct DatasetLoad {
    LineSet lines;
    ParticleData particles;  // particle datasets: one or more frames; `lines` is empty then
    CleanReport cleaned;     // what was skipped (NaN/Inf, duplicates, short polylines)
    std::string source;      // the path, or "generate:tornado(lines=..,points=..,seed=..)"
    double seconds = 0;

    bool isParticles() const { return !particles.frames.empty(); }
};

// A partitioned line set (io/partition.h) is read whole: every brick, each segment once.
// Throws InputError for unreadable data; a dataset with no polylines left after cleaning is an
// error naming the file and what was skipped. A file with no polylines at all is an empty dataset.
DatasetLoad loadDataset(const DatasetSpec& spec);

// Whether `path` names a dataset file by its extension (a line, particle or VTK format) or is a
// partitioned line set (io/partition.h: its directory or index.json), as opposed to a scene (.json).
bool isDatasetFile(const std::string& path);

}  // namespace tc
