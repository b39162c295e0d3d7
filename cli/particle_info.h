#pragma once
// `tubecast info` for particle files: frames, particle counts, bounds, radii and attributes.
#include <string>

#include "core/particle_set.h"

namespace tc::cli {

// Reads the particle file at `path` (io/particle_reader.h) and prints its summary to stdout, as
// text or (json) one JSON object. Throws InputError for unreadable files.
void printParticleInfo(const std::string& path, bool json);
// The same for particles already loaded (a VTK point cloud, a scene's dataset); `label` names
// their source in the output.
void printParticleInfo(const ParticleData& data, const std::string& label, bool json);

}  // namespace tc::cli
