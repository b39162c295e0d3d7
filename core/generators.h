#pragma once
// Built-in datasets, deterministic by seed, so the demo and the benchmarks need no download.
#include <cstdint>

#include "core/line_set.h"

namespace tc {

// The analytic tornado-like vortex of Crawfis ("gen_tornado", the flow behind VTK's and
// ParaView's tornado example) in the unit cube, traced into `lines` streamlines of `points`
// vertices each with RK4 at a fixed arc-length step. Seeds are drawn per line from the seed, so
// the result does not depend on the thread count. Attributes: "speed" (|v|), "height" (z),
// "arc_length". A streamline that leaves the cube or stalls is re-seeded (up to 32 tries) and
// otherwise kept shorter.
LineSet generateTornado(int lines, int points, std::uint32_t seed);

// The flow itself, for tests: velocity at p in the unit cube.
glm::vec3 tornadoVelocity(const glm::vec3& p);

}  // namespace tc
