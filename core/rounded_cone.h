#pragma once
// Rounded cones: the convex hull of two spheres (x0, r0) and (x1, r1), the primitive every line
// segment is drawn as (Groß & Gumhold 2020, Sect. 5.1). shaders/rounded_cone.glsl is the GPU twin
// of this file: same math, same names, same edge cases; keep them in lock-step.
#include <glm/glm.hpp>
#include <optional>

#include "core/camera.h"

namespace tc {

struct RoundedCone {
    glm::vec3 x0;
    float r0;
    glm::vec3 x1;
    float r1;
};

// Where a ray is inside a rounded cone: the whole entry/exit interval along the ray, t possibly
// negative (the ray origin may be inside; the caller decides which t it wants). Normals are
// outward and unit length. On a miss hit = false and the other fields are 0.
struct ConeInterval {
    bool hit;
    float tIn, tOut;
    glm::vec3 nIn, nOut;
};

// Exact ray / rounded-cone interval: union of sphere 0, sphere 1 and the lateral surface of the
// common tangent cone between the two tangent circles (I. Quilez' rounded-cone intersector,
// extended to both roots). Handles one sphere containing the other (the shape is the bigger
// sphere), zero-length segments, r0 == r1, rays parallel to the axis and grazing rays without
// NaN. Solved in a frame whose origin is the point of the ray closest to x0, so thin tubes far
// from the ray origin keep float precision. ray.dir must be unit length; radii > 0.
ConeInterval intersectRoundedCone(const Ray& ray, const RoundedCone& cone);

// The surface a ray leaving its origin meets first: the entry when it lies ahead (t > 0), else the
// exit (the origin is inside the cone); nothing when the whole interval lies behind the origin or
// the ray misses. The opaque visible-surface rule of the CPU reference and the Embree path.
struct SurfaceHit {
    float t;
    glm::vec3 normal;
};
std::optional<SurfaceHit> nearestPositiveHit(const ConeInterval& iv);
// nearestPositiveHit(intersectRoundedCone(ray, cone)), bit for bit, normalizing only the normal it
// returns: the per-pixel test of the CPU reference and of the Embree path's exact re-intersection.
std::optional<SurfaceHit> firstSurfaceHit(const Ray& ray, const RoundedCone& cone);

// Signed distance from p to the rounded cone: exact outside; inside negative, with the magnitude
// of the distance to the boundary piece (sphere 0, lateral, sphere 1) whose region holds p, so
// the sign is exact everywhere and the value continuous.
float sdRoundedCone(glm::vec3 p, const RoundedCone& cone);

// Double-precision twins, for tests that measure the float versions.
struct RoundedConeD {
    glm::dvec3 x0;
    double r0;
    glm::dvec3 x1;
    double r1;
};
struct RayD {
    glm::dvec3 origin;
    glm::dvec3 dir;  // unit length
};
struct ConeIntervalD {
    bool hit;
    double tIn, tOut;
    glm::dvec3 nIn, nOut;
};
ConeIntervalD intersectRoundedCone(const RayD& ray, const RoundedConeD& cone);
double sdRoundedCone(const glm::dvec3& p, const RoundedConeD& cone);

}  // namespace tc
