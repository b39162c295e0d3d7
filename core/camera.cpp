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
      m_right(camera.right()),
      m_up(camera.trueUp()),
      m_width(float(width)),
      m_height(float(height)),
      m_aspect(float(width) / float(height)),
      m_halfExtent(camera.projection == Projection::Orthographic ? 0.5f * camera.orthoHeight
                                                                 : std::tan(glm::radians(camera.fovYDeg) * 0.5f)),
      m_ortho(camera.projection == Projection::Orthographic) {}

Ray PixelRays::operator()(float px, float py) const {
    // NDC of the pixel centre; py = 0 is the top row.
    float sx = 2.0f * (px + 0.5f) / m_width - 1.0f;
    float sy = 1.0f - 2.0f * (py + 0.5f) / m_height;
    float h = m_halfExtent;
    if (m_ortho) return {m_eye + (sx * h * m_aspect) * m_right + (sy * h) * m_up, m_forward};
    return {m_eye, glm::normalize(m_forward + (sx * h * m_aspect) * m_right + (sy * h) * m_up)};
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
