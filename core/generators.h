#pragma once
// Built-in datasets, deterministic by seed, so the demo and the benchmarks need no download.
#include <cstdint>
#include <string>
#include <vector>

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

// Stand-ins for the four kinds of data in the performance tables of Groß & Gumhold 2020 (a sparse
// propeller wake, dense fiber tracts, convection cells, domain-filling turbulence). All are
// deterministic by seed and independent of the thread count (every line draws from its own
// generator seeded by (seed, line index)); the shape of each field is fixed, the seed chooses
// the seed points. Unless said otherwise a data set has exactly `lines` polylines of exactly
// `points` vertices, so lines x (points - 1) segments (docs/scene-spec.md).

// Rotor wake: a jet along z through the axis x = y = 0.5 with swirl, contraction and a 3-bladed
// helical wobble. Streamlines start at the trailing edges of 3 blades (z ~ 0.02, r in
// [0.12, 0.42]) and run up the wake: 3 helical sheets of long lines and much empty space. Time
// is integrated (not arc length), T chosen so that no line passes z = 0.98; r only shrinks, so
// all vertices lie in the cylinder r <= 0.42 inside the unit cube. Attributes: "speed",
// "vorticity" (|curl v|, central differences), "height" (z), "radius" (distance to the axis).
LineSet generatePropeller(int lines, int points, std::uint32_t seed);
glm::vec3 propellerVelocity(const glm::vec3& p);

// Fiber tracts: short fibers packed in the ellipsoid centred at (0.5, 0.5, 0.5) with semi-axes
// (0.36, 0.45, 0.32), in 24 bundles (a fixed layout). Each bundle is a helical direction field
// (circular arcs of radius 0.15..0.5 around a bundle axis, slightly twisted); a fiber follows its
// bundle's field (RK4 at a fixed arc-length step) symmetrically about a seed near the bundle's
// centre, with a per-fiber length of about 0.1..0.4. A fiber that would leave the ellipsoid is
// re-seeded (up to 16 times), else placed at the bundle centre shortened to fit. Attributes:
// "bundle" (index 0..23), "arc_length", "depth" (ellipsoidal radius: 0 at the centre, 1 on the
// surface).
LineSet generateBrain(int lines, int points, std::uint32_t seed);
constexpr int kBrainBundles = 24;
glm::vec3 brainBundleDirection(int bundle, const glm::vec3& p);  // unit vector
bool insideBrain(const glm::vec3& p);

// Rayleigh-Benard-Poiseuille convection: 4 counter-rotating longitudinal rolls (axes along y,
// width and height 0.25) in the slab [0,1] x [0,1] x [0,0.25] with a weak parabolic through-flow
// along y, so streamlines are helices around the roll axes. The slab is invariant (u = 0 on the
// roll walls, w = 0 on top and bottom); time integration, seeds drawn so that no line reaches
// y = 1. Attributes: "speed", "vorticity" (analytic), "temperature" (conductive profile plus
// the roll's perturbation, warm where the fluid rises).
LineSet generateConvection(int lines, int points, std::uint32_t seed);
glm::vec3 convectionVelocity(const glm::vec3& p);
constexpr float kConvectionHeight = 0.25f;

// Turbulence: the unit cube is one period of a 2*pi-periodic flow (ABC flow, A = sqrt 3,
// B = sqrt 2, C = 1, plus 8 random divergence-free Fourier modes with a k^-5/3 spectrum at
// wavenumbers 2..6, a fixed set), so streamlines fill the domain. Every line is traced for
// `points` vertices; where it crosses a face it continues from the opposite face as a new
// polyline (the crossing segment is not drawn, single-vertex pieces are dropped), so segments =
// lines x (points - 1) - crossings and polylines >= lines. Attributes: "speed", "vorticity"
// (analytic), both in the flow's own (2*pi-periodic) units.
LineSet generateTurbulence(int lines, int points, std::uint32_t seed);
glm::vec3 turbulenceVelocity(const glm::vec3& p);  // p in unit-cube coordinates, periodic

// Spirals: every line winds kSpiralTurns times around its own random axis on a sphere about the
// centre (0.5, 0.5, 0.5), from polar angle 0.05 pi to 0.95 pi at a constant rate per vertex; the
// spheres' radii are uniform in volume between 0.15 and 0.5, so the lines fill the ball of radius
// 0.5 (the benchmark scene of the bare Embree baseline, configs/bench/spiral_1m.json). Exactly
// `lines` polylines of `points` vertices; no vector field behind them. Attributes: "shell" (the
// line's sphere radius), "parameter" (0 at the first vertex, 1 at the last).
LineSet generateSpiral(int lines, int points, std::uint32_t seed);
constexpr int kSpiralTurns = 3;
constexpr float kSpiralMinShell = 0.15f, kSpiralMaxShell = 0.5f;

// The names dataset.generate accepts, and dispatch by name (throws std::invalid_argument on an
// unknown name: the scene parser validated it already).
const std::vector<std::string>& generatorNames();
LineSet generateDataset(const std::string& name, int lines, int points, std::uint32_t seed);

}  // namespace tc
