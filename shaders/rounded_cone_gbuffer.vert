// Vertex pulling: 4 corners (two indexed triangles) per segment, no vertex buffers. The quad's corners
// come from the billboard pre-pass (BILLBOARDS_PRECOMPUTED, the default) or are built here, once
// per vertex (BILLBOARDS_IN_VERTEX_SHADER, kept for the measurements in docs/performance.md).
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "billboard.glsl"
#include "line_buffers.glsl"
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
    // The quad's 4 corners in triangle-strip order, drawn as the indexed triangles 0-1-2 and 1-3-2
    // (gl/quad_indices.h).
    uint segment = segmentOfSlot(uint(gl_VertexID) / 4u);
    int corner = gl_VertexID % 4;
    vSegment = segment;
    // Flat varyings come from each triangle's provoking vertex (the last one, GL's default: corner 2
    // of both), so only that corner fetches them.
    bool provoking = corner == 2;
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
