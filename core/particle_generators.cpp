#include "core/particle_generators.h"

#include <tbb/parallel_for.h>

#include <cmath>

namespace tc {

namespace {

// Radius + 3 surface widths from each centre stays inside the unit cube.
constexpr float kDropletRadius = 0.2f;
constexpr float kSurfaceWidth = 0.015f;
const glm::vec3 kCenters[2] = {{0.31f, 0.48f, 0.5f}, {0.69f, 0.52f, 0.5f}};

// splitmix64: a stateless, platform-independent stream per chunk (std:: distributions are not
// specified bit for bit across standard libraries; the data must not change with the platform).
struct SplitMix {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }  // [0, 1)
};

float profile(const glm::vec3& p, int droplet) {
    return 0.5f * (1.0f - std::tanh((glm::length(p - kCenters[droplet]) - kDropletRadius) / kSurfaceWidth));
}

}  // namespace

ParticleSet generateDroplets(int count, std::uint32_t seed) {
    ParticleSet set;
    const std::size_t n = std::size_t(std::max(count, 0));
    set.positions.resize(n);
    set.radii.resize(n);
    Attribute density{"density", std::vector<float>(n)}, droplet{"droplet", std::vector<float>(n)},
        velocity{"velocity_x", std::vector<float>(n)};
    const float volume = 2.0f * 4.0f / 3.0f * 3.14159265f * kDropletRadius * kDropletRadius * kDropletRadius;
    const float sigma = std::cbrt(volume / float(std::max<std::size_t>(n, 1)));
    constexpr std::size_t kChunk = 4096;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t chunk) {
        SplitMix rng{(std::uint64_t(seed) << 32) ^ (chunk * 0xD1B54A32D192ED03ull)};
        const std::size_t end = std::min(n, (chunk + 1) * kChunk);
        for (std::size_t i = chunk * kChunk; i < end; ++i) {
            // A droplet, then a point in its bounding cube accepted with probability = the summed
            // profile / 2 (the profile's maximum): the particles follow the density.
            const int d = int(rng.next() & 1u);
            const float extent = kDropletRadius + 3.0f * kSurfaceWidth;
            glm::vec3 p;
            float rho;
            do {
                p = kCenters[d] + extent * glm::vec3(2.0f * rng.uniform() - 1.0f, 2.0f * rng.uniform() - 1.0f,
                                                     2.0f * rng.uniform() - 1.0f);
                rho = profile(p, 0) + profile(p, 1);
            } while (rng.uniform() * 2.0f >= rho);
            set.positions[i] = p;
            set.radii[i] = 0.5f * sigma;
            density.values[i] = rho;
            droplet.values[i] = float(d);
            // Head-on momentum, damped where the two droplets overlap (the collision zone).
            velocity.values[i] = (d == 0 ? 1.0f : -1.0f) * (2.0f - rho);
        }
    });
    set.attributes = {std::move(density), std::move(droplet), std::move(velocity)};
    set.update();
    return set;
}

}  // namespace tc
