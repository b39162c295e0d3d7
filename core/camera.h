#pragma once
// Cameras and the rays through pixel centres. The GPU shaders build rays with the same formula
// (shaders/camera.glsl), so CPU references and GPU images agree per pixel.
#include <glm/glm.hpp>

namespace tc {

enum class Projection { Perspective, Orthographic };

struct Camera {
    glm::vec3 eye{0.0f, 0.0f, 3.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovYDeg = 35.0f;  // vertical field of view (perspective)
    Projection projection = Projection::Perspective;
    float orthoHeight = 2.0f;  // world units covered vertically (orthographic)

    // Right-handed orthonormal camera basis; forward points from eye to target.
    glm::vec3 forward() const;
    glm::vec3 right() const;
    glm::vec3 trueUp() const;
    glm::mat4 worldToCamera() const;  // view matrix (camera looks down -z)
};

struct Ray {
    glm::vec3 origin;
    glm::vec3 dir;  // unit length
};

// Ray through the centre of pixel (px, py) of a width x height image; py = 0 is the TOP row.
// Perspective rays start at the eye; orthographic rays start on the plane through the eye.
// View-space depth of a point p is dot(p - eye, forward()).
Ray pixelRay(const Camera& camera, int width, int height, float px, float py);

// pixelRay with the camera basis computed once: the CPU ray casters generate millions of rays per
// frame, and the basis (two normalisations and crosses per call) cost as much as the ray itself.
// Gives bit-identical rays to pixelRay (which is implemented with it).
//
// A ray is an affine function of the sample's window coordinate (x, y) = (px + 0.5, height - py -
// 0.5) (y up, as gl_FragCoord): v = base + x dx + y dy is the direction before normalisation
// (perspective; the origin is the eye) or the origin (orthographic; the direction is forward).
// The GL passes evaluate the same three vectors (gl/frame_uniforms.h, shaders/camera.glsl
// pixelRay): two multiply-adds per component and a normalisation per fragment instead of the
// divisions by the image size and both projections' code, which llvmpipe runs for every lane
// (docs/performance.md, "Multiples of the constant-colour floor").
class PixelRays {
public:
    PixelRays(const Camera& camera, int width, int height);
    Ray operator()(float px, float py) const;
    const glm::vec3& base() const { return m_base; }
    const glm::vec3& dx() const { return m_dx; }
    const glm::vec3& dy() const { return m_dy; }

private:
    glm::vec3 m_eye, m_forward;
    glm::vec3 m_base, m_dx, m_dy;
    float m_height;
    bool m_ortho;
};

// Projection (OpenGL clip space, depth 0..1 not used by the ray casters) for near/far planes.
glm::mat4 projectionMatrix(const Camera& camera, float aspect, float zNear, float zFar);

}  // namespace tc
