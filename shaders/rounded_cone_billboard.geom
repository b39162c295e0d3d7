// Builds one segment's billboard (Groß & Gumhold 2020, Sect. 5.1) as a 4-vertex strip.
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "billboard.glsl"
#include "line_buffers.glsl"
#define SEGMENT_VARYINGS_OUT
#define FRAME_VARYINGS_OUT
#include "segment_varyings.glsl"

layout(points) in;
layout(triangle_strip, max_vertices = 4) out;

#include "frame_uniforms.glsl"

#include "hierarchical_culling.glsl"

flat in uint vSegmentIn[];
flat out uint vSegment;

void main() {
    uint segment = vSegmentIn[0];
    vec4 a = positionRadius[segmentVertices[2u * segment]];
    vec4 b = positionRadius[segmentVertices[2u * segment + 1u]];
    Billboard bb = computeBillboard(billboardCone(a, b), uViewProj, uEye, uOrthographic, uForward);
    if (bb.culled) return;
#ifdef CULLING
    // Depth slices (Groß & Gumhold 2020, Sect. 4.3): a hidden segment emits nothing.
    if (!bb.fullscreen && cullBillboard(bb.ndc, cullNearestDepth(a, b))) {
        atomicCounterIncrement(uCulledSegments);
        return;
    }
#endif
    SegmentVaryings varyings = loadSegmentVaryings(segment);
    for (int k = 0; k < 4; ++k) {
        vSegment = segment;
        writeSegmentVaryings(varyings);
        writeFrameVaryings();
        gl_Position = vec4(targetNdc(bb.ndc[k]), 0.0, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
