// Per-frame camera uniforms shared by the passes that cast rays per pixel; the renderer sets
// them from the same tc::Camera the CPU references use. GLSL 4.50 chunk, #include'd after
// camera.glsl.
uniform vec3 uEye;
uniform vec3 uForward;
uniform vec3 uRight;
uniform vec3 uUp;
uniform bool uOrthographic;
uniform float uTanHalfFov;
uniform float uOrthoHalfHeight;
uniform vec2 uViewport;
#include "view_window.glsl"

RayCamera frameCamera() {
    return RayCamera(uEye, uForward, uRight, uUp, uTanHalfFov, uOrthoHalfHeight, uOrthographic, uViewport,
                     uPixelOffset);
}

// View-space depth of a hit at parameter t: distance along the viewing direction. Orthographic
// rays start on the eye plane and run along it, so t is the depth.
float viewDepth(Ray ray, float t) {
    return uOrthographic ? t : t * dot(ray.dir, uForward);
}
