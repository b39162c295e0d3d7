#pragma once
// The part of space a camera's pixel rays can reach, as five planes: the four sides of the view
// frustum (perspective) or slab (orthographic) of a width x height image, grown by a margin in
// pixels, and the plane through the eye (rays start there and go forward). Used to move what
// lies entirely outside the view to the end of the draw order (gl/segment_order.h): it cannot
// rasterize a fragment, so depth slices are made of what is in view.
#include <array>
#include <glm/glm.hpp>

#include "core/camera.h"

namespace tc {

struct ViewFrustum {
    // Inward unit normal xyz and offset w: a point p is on the inner side when dot(xyz, p) + w >= 0.
    std::array<glm::vec4, 5> planes;

    // Whether the sphere (centre, radius) lies entirely on the outer side of one plane, so no
    // pixel ray of the image can meet it.
    bool excludesSphere(const glm::vec3& centre, float radius) const {
        for (const glm::vec4& p : planes)
            if (glm::dot(glm::vec3(p), centre) + p.w < -radius) return true;
        return false;
    }
};

// `marginPixels` >= 0 grows the image on every side (pixel-centre jitter of image.samples is at
// most half a pixel; rasterizers round). width, height > 0: the full image, not a tile.
ViewFrustum viewFrustum(const Camera& camera, int width, int height, float marginPixels);

}  // namespace tc
