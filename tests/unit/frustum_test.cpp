// core/frustum.h: a sphere the view frustum excludes is met by no pixel ray of the image (pixel
// centres and the corners of every pixel, i.e. any jitter), for perspective and orthographic
// cameras; and the test is not vacuous: most spheres scattered around the camera are excluded.
#include "core/frustum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/camera.h"

namespace tc::test {
namespace {

// Whether the ray meets the sphere at some t >= 0.
bool rayMeetsSphere(const Ray& ray, const glm::vec3& c, float r) {
    const glm::vec3 m = c - ray.origin;
    const float along = glm::dot(m, ray.dir);
    const float miss2 = glm::dot(m, m) - along * along;
    if (miss2 > r * r) return false;
    return along + std::sqrt(r * r - miss2) >= 0.0f;
}

void checkCamera(const Camera& cam, std::uint32_t seed) {
    const int w = 40, h = 24;
    const ViewFrustum frustum = viewFrustum(cam, w, h, 0.0f);
    const PixelRays rays(cam, w, h);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-3.0f, 3.0f), rad(0.01f, 0.3f);
    int excluded = 0, seen = 0;
    const int spheres = 2000;
    for (int i = 0; i < spheres; ++i) {
        const glm::vec3 c = cam.eye + glm::vec3(pos(rng), pos(rng), pos(rng));
        const float r = rad(rng);
        bool met = false;
        // Pixel corners and centres: every sample position jitter can produce.
        for (int y = 0; y <= 2 * h && !met; ++y)
            for (int x = 0; x <= 2 * w && !met; ++x)
                met = rayMeetsSphere(rays(0.5f * float(x) - 0.5f, 0.5f * float(y) - 0.5f), c, r);
        if (met) ++seen;
        if (frustum.excludesSphere(c, r)) {
            ++excluded;
            EXPECT_FALSE(met) << "sphere " << i << " at (" << c.x << ", " << c.y << ", " << c.z << ") r " << r;
        }
    }
    EXPECT_GT(seen, 0);
    EXPECT_GT(excluded, spheres / 2) << "of " << spheres;
}

TEST(Frustum, excluded_spheres_are_met_by_no_pixel_ray_perspective) {
    Camera cam;
    cam.eye = {0.3f, -0.2f, 1.0f};
    cam.target = {1.0f, 0.5f, -0.4f};
    cam.up = {0, 0, 1};
    cam.fovYDeg = 30.0f;
    checkCamera(cam, 1);
    cam.fovYDeg = 100.0f;
    checkCamera(cam, 2);
}

TEST(Frustum, excluded_spheres_are_met_by_no_pixel_ray_orthographic) {
    Camera cam;
    cam.eye = {0.0f, 0.0f, 2.0f};
    cam.target = {0.2f, 0.1f, 0.0f};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 1.5f;
    checkCamera(cam, 3);
}

TEST(Frustum, the_margin_keeps_spheres_just_outside_the_image) {
    Camera cam;
    cam.eye = {0, 0, 0};
    cam.target = {0, 0, -1};
    cam.fovYDeg = 60.0f;
    const int w = 100, h = 100;
    // Centre 1 pixel (at unit distance) beyond the right edge, tiny radius.
    const float pixel = 2.0f * std::tan(glm::radians(30.0f)) / float(h);
    const glm::vec3 c = glm::vec3(std::tan(glm::radians(30.0f)) + pixel, 0.0f, -1.0f) * 10.0f;
    EXPECT_TRUE(viewFrustum(cam, w, h, 0.0f).excludesSphere(c, 0.01f * pixel));
    EXPECT_FALSE(viewFrustum(cam, w, h, 2.0f).excludesSphere(c, 0.01f * pixel));
    // Behind the eye.
    EXPECT_TRUE(viewFrustum(cam, w, h, 2.0f).excludesSphere({0, 0, 1}, 0.5f));
    EXPECT_FALSE(viewFrustum(cam, w, h, 2.0f).excludesSphere({0, 0, 0.4f}, 0.5f));
}

}  // namespace
}  // namespace tc::test
