#include "core/camera.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace tc {

glm::vec3 Camera::forward() const {
    return glm::normalize(target - eye);
}

glm::vec3 Camera::right() const {
    glm::vec3 r = glm::cross(forward(), up);
    // up parallel to the view direction: pick any perpendicular axis rather than produce NaN.
    if (glm::dot(r, r) < 1e-12f)
        r = glm::cross(forward(), std::abs(forward().y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0));
    return glm::normalize(r);
}

glm::vec3 Camera::trueUp() const {
    return glm::cross(right(), forward());
}

glm::mat4 Camera::worldToCamera() const {
    glm::vec3 f = forward(), r = right(), u = trueUp();
    glm::mat4 m(1.0f);
    m[0][0] = r.x;
    m[1][0] = r.y;
    m[2][0] = r.z;
    m[0][1] = u.x;
    m[1][1] = u.y;
    m[2][1] = u.z;
    m[0][2] = -f.x;
    m[1][2] = -f.y;
    m[2][2] = -f.z;
    m[3][0] = -glm::dot(r, eye);
    m[3][1] = -glm::dot(u, eye);
    m[3][2] = glm::dot(f, eye);
    return m;
}

PixelRays::PixelRays(const Camera& camera, int width, int height)
    : m_eye(camera.eye),
      m_forward(camera.forward()),
      m_height(float(height)),
      m_ortho(camera.projection == Projection::Orthographic) {
    // The image rectangle at unit distance (perspective) or on the eye plane (orthographic): half
    // extents h * aspect and h, swept by x in [0, width] and y in [0, height].
    const float h = m_ortho ? 0.5f * camera.orthoHeight : std::tan(glm::radians(camera.fovYDeg) * 0.5f);
    const float aspect = float(width) / float(height);
    const glm::vec3 right = camera.right(), up = camera.trueUp();
    m_dx = (2.0f * h * aspect / float(width)) * right;
    m_dy = (2.0f * h / float(height)) * up;
    m_base = (m_ortho ? m_eye : m_forward) - (h * aspect) * right - h * up;
}

Ray PixelRays::operator()(float px, float py) const {
    // Window coordinates of the pixel centre; py = 0 is the top row, y = 0 the bottom edge.
    const float x = px + 0.5f, y = m_height - (py + 0.5f);
    const glm::vec3 v = m_base + x * m_dx + y * m_dy;
    if (m_ortho) return {v, m_forward};
    return {m_eye, glm::normalize(v)};
}

Ray pixelRay(const Camera& camera, int width, int height, float px, float py) {
    return PixelRays(camera, width, height)(px, py);
}

glm::mat4 projectionMatrix(const Camera& camera, float aspect, float zNear, float zFar) {
    if (camera.projection == Projection::Orthographic) {
        float h = 0.5f * camera.orthoHeight;
        return glm::ortho(-h * aspect, h * aspect, -h, h, zNear, zFar);
    }
    return glm::perspective(glm::radians(camera.fovYDeg), aspect, zNear, zFar);
}

}  // namespace tc
