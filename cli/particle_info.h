#pragma once
// `tubecast info` for particle files (M6): frames, particle counts, bounds, radii and attributes.
#include <string>

namespace tc::cli {

// Reads the particle file at `path` (io/particle_reader.h) and prints its summary to stdout, as
// text or (json) one JSON object. Throws InputError for unreadable files.
void printParticleInfo(const std::string& path, bool json);

}  // namespace tc::cli
