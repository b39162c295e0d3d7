// Rays through pixel centres: the GPU twin of tc::pixelRay (core/camera.cpp), same formula and
// operation order so CPU references and GPU images agree per pixel. GLSL 4.50 chunk, #include'd.
#ifndef TC_CAMERA_GLSL
#define TC_CAMERA_GLSL

struct Ray {
    vec3 origin;
    vec3 dir;  // unit length
};

// What the shader needs of a tc::Camera, filled from uniforms:
//   forward = Camera::forward(),
//   tanHalfFovY = std::tan(glm::radians(fovYDeg) * 0.5f), orthoHalfHeight = 0.5f * orthoHeight,
//   viewport = (width, height) of the full image in pixels, pixelOffset = the full-image window
//   coordinate of the render target's origin (shaders/frame_uniforms.glsl; 0 untiled).
struct RayCamera {
    vec3 eye;
    vec3 forward;
    float tanHalfFovY;
    float orthoHalfHeight;
    bool orthographic;
    vec2 viewport;
    vec2 pixelOffset;
    // The rays as base + x dx + y dy of the full-image window coordinate (x, y): direction before
    // normalisation (perspective) or origin (orthographic); tc::PixelRays base(), dx(), dy().
    vec3 rayBase;
    vec3 rayDx;
    vec3 rayDy;
};

// Ray through the pixel whose centre is at window coordinate fragCoord (gl_FragCoord.xy: y = 0.5
// is the BOTTOM row, which is tc::pixelRay's py = height - 1) of the render target, shifted by
// pixelOffset into the full image. Perspective rays start at the eye; orthographic rays start on
// the plane through the eye.
Ray pixelRay(RayCamera cam, vec2 fragCoord) {
    vec2 p = fragCoord + cam.pixelOffset;
    vec3 v = cam.rayBase + p.x * cam.rayDx + p.y * cam.rayDy;
    Ray ray;
    ray.origin = cam.orthographic ? v : cam.eye;
    ray.dir = cam.orthographic ? cam.forward : normalize(v);
    return ray;
}

#endif  // TC_CAMERA_GLSL
