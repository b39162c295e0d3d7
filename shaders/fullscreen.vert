// One triangle covering the viewport; no vertex buffers. Programs compiled with
// FULLSCREEN_FRAME_VARYINGS hand their fragment shader the frame's camera and light as flat
// varyings (frame_uniforms.glsl: per-pixel uniform reads cost on llvmpipe).
#ifdef FULLSCREEN_FRAME_VARYINGS
#define FRAME_VARYINGS_OUT
#include "camera.glsl"
#include "frame_uniforms.glsl"
#endif

void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
#ifdef FULLSCREEN_FRAME_VARYINGS
    writeFrameVaryings();
#endif
}
