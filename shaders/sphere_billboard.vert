// Sphere glyphs (M6): vertex pulling, 6 vertices (two triangles) per particle on the rectangle that
// contains the projected sphere exactly (perspective-correct tangent bounds, sphere_glyph.glsl),
// padded by half a pixel. Depth is a constant 0.5 (NDC 0): the early-z chunks of Sect. 5.2 mark
// finished pixels with depth 0 and let the depth test reject later particles before shading.
#include "camera.glsl"
#include "frame_uniforms.glsl"
#include "sphere_glyph.glsl"

layout(std430, binding = 0) readonly buffer CenterRadius { vec4 centerRadius[]; };
#ifdef DRAW_ORDER
layout(std430, binding = 5) readonly buffer DrawOrder { uint drawOrder[]; };
#endif

flat out uint vParticle;

const int kCorner[6] = int[6](0, 1, 2, 2, 1, 3);

void main() {
    uint slot = uint(gl_VertexID) / 6u;
#ifdef DRAW_ORDER
    uint p = drawOrder[slot];
#else
    uint p = slot;
#endif
    vParticle = p;
    vec4 cr = centerRadius[p];
    vec4 rect;
    vec2 pad = 1.0 / uViewport;  // half a pixel in NDC
    if (!projectedSphereBounds(uEye, uForward, uRight, uUp, uOrthographic, uTanHalfFov, uOrthoHalfHeight,
                               uViewport.x / uViewport.y, cr.xyz, cr.w, pad, rect)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: the quad is culled
        return;
    }
    rect = clamp(rect, vec4(-1.0 - pad, -1.0 - pad), vec4(1.0 + pad, 1.0 + pad));
    int corner = kCorner[gl_VertexID % 6];
    gl_Position = vec4(targetNdc(vec2((corner & 1) == 0 ? rect.x : rect.z, (corner & 2) == 0 ? rect.y : rect.w)), 0.0, 1.0);
}
