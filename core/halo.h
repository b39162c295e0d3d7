#pragma once
// Depth-dependent halos (style.halo; Everts et al. 2009, with which Günther, Rössl & Theisel 2013,
// Sect. 4.2 draw their lines) on one segment and one ray: the CPU twin of haloFragment in
// shaders/transparent_fragment.glsl (same math, same names, same edge cases; keep them in
// lock-step). Used by the CPU reference (core/transparent_reference.h) and the Embree path
// (rt/raytraced_renderer.cpp).
//
// The ring is HaloGeometry::width tube radii wide around the tube's silhouette: the segment's
// rounded cone grown by the factor 1 + width. A ray that misses the segment's tube (no fragment by
// core/cap_clipping.h's rule) but enters the grown cone on its surface after cap clipping gives a
// halo fragment. Its depth grows linearly across the ring, from the axis depth at the silhouette
// (u = 0) to `depth` radii behind the axis at the outer edge (u = 1), as the paper's strips push
// their halo region back.
#include <glm/glm.hpp>

#include "core/cap_clipping.h"
#include "core/rounded_cone.h"
#include "core/scene.h"

namespace tc {

struct HaloGeometry {
    float width = 0.5f;  // ring width, tube radii
    float depth = 4.0f;  // depth offset at the ring's outer edge, tube radii
};

// A halo as a renderer draws it: the ring's geometry and its colour in linear RGB, in [0, 1] (the
// ring takes the line's alpha; style.halo.color is sRGB, core/scene.h haloColor).
struct LineHalo {
    HaloGeometry geometry;
    glm::vec3 color{0.0f};
};

// style.halo as drawn over image.background.
LineHalo lineHalo(const HaloSpec& spec, const glm::vec4& background);

// How far a segment's fragments reach, as a multiple of its tube's radius: 1 + the ring's width
// with style.halo, else 1 (data-parallel rendering sends a segment to every region it reaches).
inline float haloReach(const HaloSpec& spec) {
    return spec.enabled ? 1.0f + spec.width : 1.0f;
}

// The segment's cone grown by the ring: the shape whose surface a halo fragment's ray enters.
inline RoundedCone grownCone(const RoundedCone& c, const HaloGeometry& halo) {
    const float scale = 1.0f + halo.width;
    return {c.x0, c.r0 * scale, c.x1, c.r1 * scale};
}

struct HaloHit {
    float depth;       // view depth dot(q - eye, forward) + min(u, 1) depth r: the sort key, > 0
    float tEntry;      // where the ray enters the grown cone (after cap clipping)
    glm::vec3 normal;  // the grown cone's outward normal there
    float along;       // in [0, 1]: the axis point q nearest the ray; colour and alpha are read there
};

// The halo fragment of the segment `cone` (clipped by `planes`) on `ray`, for a ray that has no
// tube fragment of this segment; false when the ray misses the ring, passes within the tube's
// radius (a neighbour's surface at a joint) or the fragment lies behind the eye. `eye` and
// `forward` give view depth (camera.h: dot(p - eye, forward)).
bool haloFragment(const Ray& ray, const RoundedCone& cone, const ClipPlanes& planes, const glm::vec3& eye,
                  const glm::vec3& forward, const HaloGeometry& halo, HaloHit& out);

}  // namespace tc
