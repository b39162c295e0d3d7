#pragma once
// Where a render's radius, colour and opacity come from, as the log and run.json say it
// ("radius: constant 0.004 from the scene", "radius: element radii (C 1.7, O 1.52)"), by the
// precedence rule of docs/scene-spec.md: the scene's own entries, then what the data carries or
// implies, then the defaults.
#include <string>
#include <vector>

#include "core/particle_set.h"
#include "core/scene.h"

namespace tc {

// `particles`: the particle dataset (its first frame's radii and colours), or null for lines.
std::vector<std::string> styleSources(const StyleSpec& style, const ParticleData* particles);

}  // namespace tc
