// Vertex pulling: 4 corners (two indexed triangles) per segment, no vertex buffers. The quad's corners
// come from the billboard pre-pass (BILLBOARDS_PRECOMPUTED, the default) or are built here, once
// per vertex (BILLBOARDS_IN_VERTEX_SHADER, kept for the measurements in docs/performance.md).
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "billboard.glsl"
#include "line_buffers.glsl"
#include "quad_corners.glsl"
#define SEGMENT_VARYINGS_OUT
#define FRAME_VARYINGS_OUT
#include "segment_varyings.glsl"

#include "frame_uniforms.glsl"

#include "hierarchical_culling.glsl"

#ifdef BILLBOARDS_PRECOMPUTED
layout(std430, binding = SSBO_BILLBOARD_CORNERS) readonly buffer BillboardCorners { vec4 billboardCorners[]; };
#endif

flat out uint vSegment;

void main() {
    // The quad's 4 corners, drawn as two indexed triangles (shaders/quad_corners.glsl).
    uint segment = segmentOfSlot(quadOfVertex());
    int corner = quadCorner();
    vSegment = segment;
    // Flat varyings come from each triangle's provoking vertex, so only that corner fetches them.
    bool provoking = isProvokingCorner(corner);
#ifdef BILLBOARDS_PRECOMPUTED
    vec4 pair = billboardCorners[2u * segment + uint(corner >> 1)];
    if (provoking) {
        writeSegmentVaryings(readSegmentRecord(segment));
        writeFrameVaryings();
    }
    gl_Position = vec4(targetNdc((corner & 1) == 0 ? pair.xy : pair.zw), 0.0, 1.0);
#else
    vec4 a = positionRadius[segmentVertices[2u * segment]];
    vec4 b = positionRadius[segmentVertices[2u * segment + 1u]];
    vec2 corners[4];
    computeBillboard(billboardCone(a, b), uViewProj, uEye, uForward, uOrthographic, corners);
#ifdef CULLING
    // Depth slices: every corner of a hidden segment collapses to one point off screen. The
    // BILLBOARDS_PRECOMPUTED path culls in billboard_pass.comp instead.
    if (cullBillboard(corners, cullNearestDepth(a, b))) {
        corners[corner] = vec2(-2.0);
        if (corner == 0) atomicCounterIncrement(uCulledSegments);
    }
#endif
    gl_Position = vec4(targetNdc(corners[corner]), 0.0, 1.0);
    if (provoking) {
        writeSegmentVaryings(loadSegmentVaryings(segment));
        writeFrameVaryings();
    }
#endif
}
