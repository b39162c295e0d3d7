#include "core/halo.h"

#include <cmath>

#include "core/color.h"

namespace tc {

LineHalo lineHalo(const HaloSpec& spec, const glm::vec4& background) {
    // Clamped once here as every transparent path clamps its colours (the k-buffer stores RGBA8).
    return {{spec.width, spec.depth}, glm::clamp(srgbToLinear(haloColor(spec, background)), 0.0f, 1.0f)};
}

bool haloFragment(const Ray& ray, const RoundedCone& c, const ClipPlanes& planes, const glm::vec3& eye,
                  const glm::vec3& forward, const HaloGeometry& halo, HaloHit& out) {
    const ConeInterval ring = intersectRoundedCone(ray, grownCone(c, halo));
    if (!ring.hit) return false;
    float tEntry;
    glm::vec3 nEntry;
    if (!segmentFragment(ray, ring, planes, tEntry, nEntry)) return false;
    // The ray's closest approach to the axis: the middle of its chord through the grown cone
    // (exact for a cylinder and for the end spheres).
    const glm::vec3 mid = ray.origin + 0.5f * (ring.tIn + ring.tOut) * ray.dir;
    const glm::vec3 axis = c.x1 - c.x0;
    const float len2 = glm::dot(axis, axis);
    const float s = len2 > 0.0f ? glm::clamp(glm::dot(mid - c.x0, axis) / len2, 0.0f, 1.0f) : 0.0f;
    const glm::vec3 q = c.x0 + s * axis;
    const float radius = glm::mix(c.r0, c.r1, s);
    const float u = (glm::distance(mid, q) - radius) / (halo.width * radius);
    // Within the tube's radius but not this segment's surface: a neighbour's at a joint.
    if (!(u >= 0.0f)) return false;
    out.depth = glm::dot(q - eye, forward) + std::min(u, 1.0f) * halo.depth * radius;
    if (!(out.depth > 0.0f)) return false;
    out.tEntry = tEntry;
    out.normal = nEntry;
    out.along = s;
    return true;
}

}  // namespace tc
