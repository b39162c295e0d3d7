#pragma once
// The technique registry of the tubecast binary: every GL technique (gl/techniques.h) and every
// CPU one (rt/techniques.h), registered once. cli/ reaches techniques only through it.
#include "core/technique_registry.h"

namespace tc::cli {

const TechniqueRegistry& techniqueRegistry();

}  // namespace tc::cli
