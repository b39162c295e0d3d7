#include "core/vrc_lighting.h"

#include <algorithm>
#include <cmath>

namespace tc {

float sampleVrcDensity(const VrcDensityLevel& level, glm::vec3 p) {
    const glm::vec3 c = p - 0.5f;
    const glm::vec3 base = glm::floor(c);
    const glm::vec3 f = c - base;
    const glm::ivec3 i0(base);
    float sum = 0.0f;
    for (int k = 0; k < 8; ++k) {
        const glm::ivec3 d(k & 1, (k >> 1) & 1, k >> 2);
        const glm::ivec3 i = i0 + d;
        if (glm::any(glm::lessThan(i, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(i, level.size))) continue;
        const glm::vec3 w = glm::mix(1.0f - f, f, glm::vec3(d));
        const std::size_t index =
            (std::size_t(i.z) * std::size_t(level.size.y) + std::size_t(i.y)) * std::size_t(level.size.x) +
            std::size_t(i.x);
        sum += w.x * w.y * w.z * level.density[index];
    }
    return sum;
}

glm::vec3 vrcSphereDirection(int i, int n) {
    const float goldenAngle = 2.39996323f;  // pi (3 - sqrt 5)
    const float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
    const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = float(i) * goldenAngle;
    return {s * std::cos(phi), s * std::sin(phi), z};
}

float vrcDensityRayOcclusion(const VrcDensityLevel& level0, glm::vec3 p, glm::vec3 dir, float radiusVoxels) {
    float sum = 0.0f;
    const glm::vec3 hi(level0.size);
    for (int k = 1; float(k) <= radiusVoxels; ++k) {
        const glm::vec3 q = p + float(k) * dir;
        if (glm::any(glm::lessThan(q, glm::vec3(0.0f))) || glm::any(glm::greaterThan(q, hi))) break;
        sum += sampleVrcDensity(level0, q);
        if (sum >= 1.0f) return 1.0f;
    }
    return sum;
}

float vrcSphereAmbientOcclusion(const VrcDensityLevel& level0, glm::vec3 p, int rays, float radiusVoxels) {
    float occlusion = 0.0f;
    for (int i = 0; i < rays; ++i)
        occlusion += vrcDensityRayOcclusion(level0, p, vrcSphereDirection(i, rays), radiusVoxels);
    return 1.0f - occlusion / float(rays);
}

}  // namespace tc
