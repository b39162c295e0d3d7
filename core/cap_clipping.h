#pragma once
// Cap clipping (Groß & Gumhold 2020, Sect. 5.4): consecutive rounded cones of a polyline overlap in
// the sphere of their shared vertex. Each segment is clipped against one plane per interior joint,
// so the segments of a polyline tile ONE tube and a transparent tube is entered once per ray, with
// no bright bead at its joints. shaders/cap_clipping.glsl is the GPU twin of this file: same math,
// same names, same edge cases; keep them in lock-step.
//
// The rule, precisely:
// - Joint plane. At an interior vertex x_i of a polyline, shared by segments (x_{i-1}, x_i) and
//   (x_i, x_{i+1}), the plane goes through x_i with the bisector normal
//     n_i = normalize(normalize(x_i - x_{i-1}) + normalize(x_{i+1} - x_i)).
//   A zero-length neighbour segment contributes a zero direction (so n_i is the other one's); a
//   fold (the two directions cancel to |sum| < 1e-4, a bend within ~0.006 degrees of 180) falls
//   back to n_i = the direction of the segment before. With both neighbours of zero length
//   there is no plane (both segments keep their caps). First and last vertices of a polyline
//   (VertexFlag) keep their full caps: no plane.
// - Ownership. The segment before the joint keeps n_i . (p - x_i) <= 0, the one after keeps >= 0.
//   Both derive the plane from the same three vertices with the same operations, so the two sides
//   are complementary up to the plane itself: every point near the joint belongs to one segment.
// - Interval. A segment's visible part along a ray is [tIn, tOut] of its rounded cone intersected
//   with its (up to two) half-spaces: a convex piece, so again one interval [a, b]; empty unless
//   a < b. Each end is either on the tube surface (from tIn / tOut) or on a clip plane.
// - Fragment (transparent paths: CPU reference, k-buffer, depth peeling). A segment contributes
//   at most one fragment per ray: at a if a > 0 and a lies on the tube surface (an entry through a
//   clip plane is the continuation of the neighbour's piece, which already counted the entry);
//   else, when the ray origin is inside the piece (a <= 0 < b), at b if b lies on the surface (the
//   inner wall, as in the opaque reference). The fragment's normal is the tube's outward normal
//   there. Without cap clipping the same rule with no planes gives tIn if > 0, else tOut if > 0.
//
// What this guarantees and where it stops:
// - Constant radius, any bend short of a fold: the clipped pieces tile the union of the rounded
//   cones exactly. Both pieces' sections in the bisector plane are the same curve (mirror symmetry:
//   half ellipse on the inner side of the bend, half circle of the joint sphere on the outer side),
//   the two cylinders meet in that plane, and the outer elbow is the joint sphere. So along any ray
//   the clipped intervals concatenate to the intervals of the union and every entry into the
//   union is counted exactly once.
// - Straight polylines with varying radius: both pieces' sections in the (perpendicular) joint
//   plane are the joint sphere's great circle, so the pieces still join without gap or overlap.
//   The tube is slightly thinner than the union of the cones near the joint (the thin ring of the
//   narrower cone's lateral surface between the plane and its tangent circle is cut away): still
//   one entry per ray, the silhouette moves by O(r sin^2 alpha) for cone half-angle alpha.
// - Bends WITH radius changes: the two cones' lateral surfaces no longer cross in the bisector
//   plane, so their sections differ by a thin crescent on the inner side of the bend, of width about
//   r |s_{i-1} - s_i| tan(theta/2) (s = radius slope dr/dL, theta the bend angle). Rays through a
//   crescent can see a hole (the union is entered through an exposed clip-plane face: no fragment)
//   or enter twice (leave one piece through the exposed face, enter the next through its surface).
// - Short segments or very sharp bends: a segment's two planes must not meet inside its tube,
//   about L > r_0 tan(theta_0 / 2) + r_1 tan(theta_1 / 2). When they do, or when a bisector
//   plane reaches past the neighbour's far joint (near folds, tan(theta/2) grows without bound),
//   pieces of non-adjacent segments overlap (doubled entries, a bright spot) or a region is
//   owned by nobody (holes, a dark/see-through spot). Non-adjacent segments of a polyline are never
//   clipped against each other: a polyline crossing itself composites as two layers, correctly.
// - Eye inside a tube: only the piece holding the ray origin counts its exit. If the view ray
//   crosses a joint plane before leaving the tube, the exit lies in another piece whose entry is on
//   a plane at t > 0, so that pixel gets no fragment from this polyline (the opaque reference
//   would show the inner wall).
// - Rays through the rim of a joint section (a measure-zero set: the plane meets the surface) can
//   count 0 or 2 entries from rounding, since the two neighbours' tIn come from different cones.
#include <cstddef>
#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/rounded_cone.h"
#include "core/styled_lines.h"

namespace tc {

// The clip planes of one segment: a point p is kept by plane P when dot(P.xyz, p) + P.w >= 0.
// p0 belongs to the segment's first vertex, p1 to its second; clipN == false means a full cap
// there (end of polyline or no defined plane), and then pN is 0.
struct ClipPlanes {
    glm::vec4 p0{0.0f}, p1{0.0f};
    bool clip0 = false, clip1 = false;
};

// Unit normal of the joint plane at x between the segments (prev, x) and (x, next), oriented along
// the polyline (the segment after keeps the positive side), or 0 when there is no plane (both
// neighbours of zero length). See the header comment for the fold and zero-length fallbacks.
glm::vec3 jointPlaneNormal(glm::vec3 prev, glm::vec3 x, glm::vec3 next);

// The planes of segment `segment` of `lines`. The polyline neighbours of its vertices are the
// adjacent vertex indices (v0 - 1, v1 + 1), the layout styleLines builds (a polyline's vertices
// are contiguous); a vertex flagged FirstOfPolyline / LastOfPolyline, or whose adjacent vertex
// belongs to another polyline id or does not exist, keeps its full cap. Segment ids may be
// permuted (sorted); vertex data is only read.
ClipPlanes segmentClipPlanes(const StyledLines& lines, std::size_t segment);

// [tEntry, tExit] of a rounded-cone interval after clipping by the half-spaces of `planes`.
// entryOnSurface / exitOnSurface say whether that end is the cone's surface (normal nEntry / nExit,
// outward) rather than a clip plane (normal 0). hit == false: the cone missed, or the planes left
// nothing (or a single point) of its interval; an unclipped grazing interval tIn == tOut is kept,
// as the opaque reference keeps it.
struct ClippedInterval {
    bool hit = false;
    float tEntry = 0.0f, tExit = 0.0f;
    bool entryOnSurface = false, exitOnSurface = false;
    glm::vec3 nEntry{0.0f}, nExit{0.0f};
};
ClippedInterval clipInterval(const Ray& ray, const ConeInterval& cone, const ClipPlanes& planes);

// The fragment rule of the transparent paths (header comment, "Fragment"): true and the ray
// parameter t > 0 and outward normal n of the one fragment this segment contributes on this ray.
bool segmentFragment(const Ray& ray, const ConeInterval& cone, const ClipPlanes& planes, float& t, glm::vec3& n);

}  // namespace tc
