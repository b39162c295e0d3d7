#pragma once
// Particles resolved by styling into what the sphere renderer draws: centre and radius,
// linear straight RGBA (alpha = Theta_max of the density model, Staib et al. 2015, Eq. 15) and
// the particle's index in its data frame (the id AOV).
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/line_set.h"

namespace tc {

struct StyledParticles {
    std::vector<glm::vec4> centerRadius;  // xyz world position, w radius (> 0)
    std::vector<glm::vec4> color;         // linear RGB, straight alpha in [0, 1]
    std::vector<std::uint32_t> id;        // index in the data frame
    Bounds bounds;                        // of the spheres (positions grown by radii)
    float maxRadius = 0;

    std::size_t size() const { return centerRadius.size(); }
};

}  // namespace tc
