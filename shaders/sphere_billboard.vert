// Sphere glyphs: vertex pulling, 4 corners (two indexed triangles) per particle on the rectangle that
// contains the projected sphere exactly (perspective-correct tangent bounds, sphere_glyph.glsl),
// padded by half a pixel. POINTS: one vertex per particle instead, a point sprite (square) around
// the same rectangle, clamped to the target: a quarter of the vertex work, which on llvmpipe runs on
// one thread and dominated the frame (docs/performance.md, "Design notes"). A sphere whose square
// exceeds the implementation's largest point size is not drawn but counted in `oversized`; the
// renderer then draws the frame again with quads. Depth is a constant 0.5 (NDC 0): the early-z
// chunks of Sect. 5.2 mark finished pixels with depth 0 and let the depth test reject later
// particles before shading.
#define FRAME_VARYINGS_OUT  // the frame's camera and light for sphere.frag (frame_uniforms.glsl)
#include "camera.glsl"
#include "frame_uniforms.glsl"
#include "sphere_glyph.glsl"
#include "quad_corners.glsl"

layout(std430, binding = SSBO_SPHERE_CENTER_RADIUS) readonly buffer CenterRadius { vec4 centerRadius[]; };
layout(std430, binding = SSBO_SPHERE_COLORS) readonly buffer Colors { vec4 colors[]; };
layout(std430, binding = SSBO_SPHERE_IDS) readonly buffer Ids { uint ids[]; };
#ifdef AMBIENT_CACHE
layout(std430, binding = SSBO_SPHERE_AMBIENT_CUBE) readonly buffer AmbientCube { uint ambientCube[]; };  // sphere_ambient_cache.comp
#endif
#ifdef DRAW_ORDER
layout(std430, binding = SSBO_SPHERE_DRAW_ORDER) readonly buffer DrawOrder { uint drawOrder[]; };
#endif

#ifdef POINTS
layout(std430, binding = SSBO_SPHERE_OVERSIZED) buffer Oversized { uint oversized; };
uniform float uMaxPointSize;
#endif

// What the fragment shader needs of the particle, as flat varyings: on llvmpipe a fragment
// shader's SSBO read is a per-lane scalar loop, a flat varying a broadcast from triangle setup.
flat out vec4 vCenterRadius;
flat out vec4 vColor;
flat out uint vId;
#ifdef AMBIENT_CACHE
flat out uvec3 vAmbientPositive;  // faces +x, +y, +z of the sphere's ambient cube
flat out uvec3 vAmbientNegative;  // faces -x, -y, -z
#endif

void main() {
#ifdef POINTS
    uint slot = uint(gl_VertexID);
#else
    // A quad's 4 corners, drawn as two indexed triangles (shaders/quad_corners.glsl).
    uint slot = quadOfVertex();
    int corner = quadCorner();
#endif
#ifdef DRAW_ORDER
    uint p = drawOrder[slot];
#else
    uint p = slot;
#endif
    vec4 cr = centerRadius[p];
#ifdef POINTS
    writeFrameVaryings();
#else
    // Flat varyings come from each triangle's provoking vertex.
    if (isProvokingCorner(corner)) writeFrameVaryings();
#endif
    vCenterRadius = cr;
    vColor = colors[p];
    vId = ids[p];
#ifdef AMBIENT_CACHE
    vAmbientPositive = uvec3(ambientCube[6u * p], ambientCube[6u * p + 2u], ambientCube[6u * p + 4u]);
    vAmbientNegative = uvec3(ambientCube[6u * p + 1u], ambientCube[6u * p + 3u], ambientCube[6u * p + 5u]);
#endif
    vec4 rect;
    vec2 pad = 1.0 / uViewport;  // half a pixel in NDC
    if (!projectedSphereBounds(uEye, uForward, uRight, uUp, uOrthographic, uTanHalfFov, uOrthoHalfHeight,
                               uViewport.x / uViewport.y, cr.xyz, cr.w, pad, rect)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: the quad is culled
        return;
    }
    rect = clamp(rect, vec4(-1.0 - pad, -1.0 - pad), vec4(1.0 + pad, 1.0 + pad));
#ifdef POINTS
    // In the target's NDC, clamped to it (a tile sees part of the image): the centre stays inside
    // the clip volume, so the point is never clipped away by its centre.
    vec2 targetPad = 1.0 / uTargetSize;
    vec2 a = targetNdc(rect.xy), b = targetNdc(rect.zw);
    vec2 lo = min(a, b), hi = max(a, b);
    if (any(lessThan(hi, vec2(-1.0) - targetPad)) || any(greaterThan(lo, vec2(1.0) + targetPad))) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // not in this target
        return;
    }
    lo = clamp(lo, -1.0 - targetPad, 1.0 + targetPad);
    hi = clamp(hi, -1.0 - targetPad, 1.0 + targetPad);
    vec2 sizePixels = 0.5 * (hi - lo) * uTargetSize;
    // + 1: the square covers every pixel centre of the rectangle whatever the rasterizer rounds.
    float size = max(sizePixels.x, sizePixels.y) + 1.0;
    if (size > uMaxPointSize) {
        atomicAdd(oversized, 1u);
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
        return;
    }
    gl_PointSize = size;
    gl_Position = vec4(0.5 * (lo + hi), 0.0, 1.0);
#else
    gl_Position = vec4(targetNdc(vec2((corner & 1) == 0 ? rect.x : rect.z, (corner & 2) == 0 ? rect.y : rect.w)), 0.0, 1.0);
#endif
}
