#include "core/camera.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace tc {

glm::vec3 Camera::forward() const { return glm::normalize(target - eye); }

glm::vec3 Camera::right() const {
    glm::vec3 r = glm::cross(forward(), up);
    // up parallel to the view direction: pick any perpendicular axis rather than produce NaN.
    if (glm::dot(r, r) < 1e-12f) r = glm::cross(forward(), std::abs(forward().y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0));
    return glm::normalize(r);
}

glm::vec3 Camera::trueUp() const { return glm::cross(right(), forward()); }

glm::mat4 Camera::worldToCamera() const {
    glm::vec3 f = forward(), r = right(), u = trueUp();
    glm::mat4 m(1.0f);
    m[0][0] = r.x; m[1][0] = r.y; m[2][0] = r.z;
    m[0][1] = u.x; m[1][1] = u.y; m[2][1] = u.z;
    m[0][2] = -f.x; m[1][2] = -f.y; m[2][2] = -f.z;
    m[3][0] = -glm::dot(r, eye);
    m[3][1] = -glm::dot(u, eye);
    m[3][2] = glm::dot(f, eye);
    return m;
}

Ray pixelRay(const Camera& camera, int width, int height, float px, float py) {
    // NDC of the pixel centre; py = 0 is the top row.
    float sx = 2.0f * (px + 0.5f) / float(width) - 1.0f;
    float sy = 1.0f - 2.0f * (py + 0.5f) / float(height);
    float aspect = float(width) / float(height);
    glm::vec3 f = camera.forward(), r = camera.right(), u = camera.trueUp();
    if (camera.projection == Projection::Orthographic) {
        float h = 0.5f * camera.orthoHeight;
        return {camera.eye + (sx * h * aspect) * r + (sy * h) * u, f};
    }
    float t = std::tan(glm::radians(camera.fovYDeg) * 0.5f);
    return {camera.eye, glm::normalize(f + (sx * t * aspect) * r + (sy * t) * u)};
}

glm::mat4 projectionMatrix(const Camera& camera, float aspect, float zNear, float zFar) {
    if (camera.projection == Projection::Orthographic) {
        float h = 0.5f * camera.orthoHeight;
        return glm::ortho(-h * aspect, h * aspect, -h, h, zNear, zFar);
    }
    return glm::perspective(glm::radians(camera.fovYDeg), aspect, zNear, zFar);
}

}  // namespace tc
