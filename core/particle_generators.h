#pragma once
// Built-in particle datasets, deterministic by seed for any thread count.
#include <cstdint>

#include "core/particle_set.h"

namespace tc {

// Two droplets of Lennard-Jones-like particles colliding off-centre in the unit cube: droplet
// spheres of radius 0.2 with a tanh surface layer, centres 0.38 apart (they already touch and
// form a neck), particles drawn by rejection sampling from the summed density profile. Every
// particle gets the radius 0.5 sigma, sigma = the mean spacing (V / N)^(1/3) of N particles in
// the droplets' volume V (the LJ contact distance). Attributes: "density" (the summed profile at
// the particle, 1 in a droplet's bulk, up to 2 in the neck), "droplet" (0 or 1: which sphere the
// particle was drawn for), "velocity_x" (the droplets move toward each other, +-1, slower in
// the neck).
ParticleSet generateDroplets(int particles, std::uint32_t seed);

}  // namespace tc
