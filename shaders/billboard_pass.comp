// Billboards once per segment (Groß & Gumhold 2020, Sect. 5.1), before the draw: llvmpipe runs
// vertex and geometry shaders single-threaded and a vertex-pulling draw would build each quad six
// times, while compute shaders run on all cores (docs/performance.md has the measurements).
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "billboard.glsl"
#include "line_buffers.glsl"
#define SEGMENT_VARYINGS_COMPUTE
#include "segment_varyings.glsl"

layout(local_size_x = 128) in;

// Two vec4 per segment: (corner0, corner1), (corner2, corner3) in NDC, triangle-strip order.
layout(std430, binding = SSBO_BILLBOARD_CORNERS) writeonly buffer BillboardCorners { vec4 billboardCorners[]; };

#include "frame_uniforms.glsl"
uniform uint uSlotEnd;    // draw slots [uFirstSlot, uSlotEnd); slot = segment without DRAW_ORDER
uniform uint uFirstSlot;  // dispatches are split to stay under the work-group count limit

#include "hierarchical_culling.glsl"

void main() {
    uint slot = uFirstSlot + gl_GlobalInvocationID.x;
    if (slot >= uSlotEnd) return;
    uint segment = segmentOfSlot(slot);
    vec4 a = positionRadius[segmentVertices[2u * segment]];
    vec4 b = positionRadius[segmentVertices[2u * segment + 1u]];
    Billboard bb = computeBillboard(billboardCone(a, b), uViewProj, uEye, uOrthographic, uForward);
#ifdef CULLING
    // Depth slices (Groß & Gumhold 2020, Sect. 4.3): a hidden segment gets the zero-area quad of
    // a culled billboard and rasterizes nothing.
    if (!bb.culled && !bb.fullscreen && cullBillboard(bb.ndc, cullNearestDepth(a, b))) {
        for (int k = 0; k < 4; ++k) bb.ndc[k] = vec2(-2.0);
        atomicCounterIncrement(uCulledSegments);
    }
#endif
    billboardCorners[2u * segment] = vec4(bb.ndc[0], bb.ndc[1]);
    billboardCorners[2u * segment + 1u] = vec4(bb.ndc[2], bb.ndc[3]);
    // What the fragment shaders need of the segment, for the vertex shader to pass on. Opaque
    // culling draws only the visibility pass, which reads the cone and its axis alone.
#ifdef CULL_MAX_DEPTH
    segmentRecord[kSegmentRecordSize * segment] = a;
    segmentRecord[kSegmentRecordSize * segment + 1u] = b;
    segmentRecord[kSegmentRecordSize * segment + 6u] = coneAxis(RoundedCone(a.xyz, a.w, b.xyz, b.w));
#else
    storeSegmentRecord(segment, loadSegmentVaryings(segment));
#endif
}
