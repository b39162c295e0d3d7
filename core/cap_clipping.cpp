#include "core/cap_clipping.h"

#include <cmath>

namespace tc {
namespace {

// Unit direction of d, or 0 for a (numerically) zero-length segment.
glm::vec3 directionOrZero(glm::vec3 d) {
    float l2 = glm::dot(d, d);
    return l2 > 1e-24f ? d / std::sqrt(l2) : glm::vec3(0.0f);
}

// dot(plane.xyz, origin + t dir) + plane.w restricts t to a half-line; returns false when the
// plane removes the whole ray. A ray parallel to the plane is kept or removed as a whole by the
// side its origin lies on (f0 / fd would be +-inf or NaN).
bool clipByPlane(const glm::vec4& plane, const Ray& ray, float& a, float& b, bool& aOnPlane, bool& bOnPlane) {
    glm::vec3 n(plane);
    float f0 = glm::dot(n, ray.origin) + plane.w;
    float fd = glm::dot(n, ray.dir);
    if (fd == 0.0f) return f0 >= 0.0f;
    float t = -f0 / fd;
    if (fd > 0.0f) {
        // Ties keep the surface: an entry exactly on the plane is still the tube's.
        if (t > a) a = t, aOnPlane = true;
    } else {
        if (t < b) b = t, bOnPlane = true;
    }
    return true;
}

}  // namespace

glm::vec3 jointPlaneNormal(glm::vec3 prev, glm::vec3 x, glm::vec3 next) {
    glm::vec3 dPrev = directionOrZero(x - prev);
    glm::vec3 dNext = directionOrZero(next - x);
    glm::vec3 sum = dPrev + dNext;
    float l2 = glm::dot(sum, sum);
    // A fold: the bisector is undefined, the previous segment's direction is not (unless it has
    // zero length too, and then dNext == 0 as well and there is no plane).
    if (l2 < 1e-8f) return dPrev;
    return sum / std::sqrt(l2);
}

ClipPlanes segmentClipPlanes(const StyledLines& lines, std::size_t segment) {
    const std::uint32_t v0 = lines.segmentVertices[2 * segment];
    const std::uint32_t v1 = lines.segmentVertices[2 * segment + 1];
    const std::size_t n = lines.vertexCount();
    auto pos = [&](std::uint32_t v) { return glm::vec3(lines.positionRadius[v]); };
    auto flag = [&](std::uint32_t v, std::uint32_t bit) { return !lines.flags.empty() && (lines.flags[v] & bit) != 0; };
    auto samePolyline = [&](std::uint32_t a, std::uint32_t b) {
        return lines.polylineId.empty() || lines.polylineId[a] == lines.polylineId[b];
    };

    ClipPlanes planes;
    if (!flag(v0, FirstOfPolyline) && v0 > 0 && samePolyline(v0 - 1, v0)) {
        glm::vec3 nrm = jointPlaneNormal(pos(v0 - 1), pos(v0), pos(v1));
        if (nrm != glm::vec3(0.0f)) {
            // The segment after the joint keeps dot(n, p - x0) >= 0.
            planes.p0 = glm::vec4(nrm, -glm::dot(nrm, pos(v0)));
            planes.clip0 = true;
        }
    }
    if (!flag(v1, LastOfPolyline) && std::size_t(v1) + 1 < n && samePolyline(v1, v1 + 1)) {
        glm::vec3 nrm = jointPlaneNormal(pos(v0), pos(v1), pos(v1 + 1));
        if (nrm != glm::vec3(0.0f)) {
            // The segment before the joint keeps dot(n, p - x1) <= 0: the same plane negated.
            planes.p1 = glm::vec4(-nrm, glm::dot(nrm, pos(v1)));
            planes.clip1 = true;
        }
    }
    return planes;
}

ClippedInterval clipInterval(const Ray& ray, const ConeInterval& cone, const ClipPlanes& planes) {
    ClippedInterval r;
    if (!cone.hit) return r;
    float a = cone.tIn, b = cone.tOut;
    bool aOnPlane = false, bOnPlane = false;
    if (planes.clip0 && !clipByPlane(planes.p0, ray, a, b, aOnPlane, bOnPlane)) return r;
    if (planes.clip1 && !clipByPlane(planes.p1, ray, a, b, aOnPlane, bOnPlane)) return r;
    // Strict: an interval that shrank to a point is a ray grazing a plane-surface edge.
    if (!(a < b) && (aOnPlane || bOnPlane)) return r;
    r.hit = true;
    r.tEntry = a;
    r.tExit = b;
    r.entryOnSurface = !aOnPlane;
    r.exitOnSurface = !bOnPlane;
    r.nEntry = aOnPlane ? glm::vec3(0.0f) : cone.nIn;
    r.nExit = bOnPlane ? glm::vec3(0.0f) : cone.nOut;
    return r;
}

bool segmentFragment(const Ray& ray, const ConeInterval& cone, const ClipPlanes& planes, float& t, glm::vec3& n) {
    ClippedInterval c = clipInterval(ray, cone, planes);
    if (!c.hit) return false;
    if (c.tEntry > 0.0f) {
        if (!c.entryOnSurface) return false;
        t = c.tEntry, n = c.nEntry;
        return true;
    }
    if (c.tExit > 0.0f && c.exitOnSurface) {
        t = c.tExit, n = c.nExit;
        return true;
    }
    return false;
}

}  // namespace tc
