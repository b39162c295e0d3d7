#include "core/frustum.h"

#include <cmath>

namespace tc {

ViewFrustum viewFrustum(const Camera& camera, int width, int height, float marginPixels) {
    const glm::vec3 f = camera.forward(), r = camera.right(), u = camera.trueUp(), eye = camera.eye;
    const bool ortho = camera.projection == Projection::Orthographic;
    // Half extents of the image plane at unit distance (perspective) or in world units
    // (orthographic), as PixelRays spans them, grown by the margin.
    const float halfY = ortho ? 0.5f * camera.orthoHeight : std::tan(glm::radians(camera.fovYDeg) * 0.5f);
    const float halfX = halfY * float(width) / float(height);
    const float hx = halfX * (1.0f + 2.0f * marginPixels / float(width));
    const float hy = halfY * (1.0f + 2.0f * marginPixels / float(height));
    auto through = [](const glm::vec3& n, const glm::vec3& point) { return glm::vec4(n, -glm::dot(n, point)); };
    ViewFrustum v;
    if (ortho) {
        // Slab sides: |dot(p - eye, r)| <= hx, |dot(p - eye, u)| <= hy.
        v.planes[0] = through(-r, eye + hx * r);
        v.planes[1] = through(r, eye - hx * r);
        v.planes[2] = through(-u, eye + hy * u);
        v.planes[3] = through(u, eye - hy * u);
    } else {
        // Side planes through the eye containing the edge directions f +- hx r (with u), f +- hy u
        // (with r); the inward normal of the one through f + hx r is hx f - r, and so on.
        v.planes[0] = through(glm::normalize(hx * f - r), eye);
        v.planes[1] = through(glm::normalize(hx * f + r), eye);
        v.planes[2] = through(glm::normalize(hy * f - u), eye);
        v.planes[3] = through(glm::normalize(hy * f + u), eye);
    }
    v.planes[4] = through(f, eye);
    return v;
}

}  // namespace tc
