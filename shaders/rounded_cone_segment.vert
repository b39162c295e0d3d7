// Geometry-shader path: one point per segment; rounded_cone_billboard.geom builds the quad (the
// paper's original structure, kept for the measurements in docs/performance.md).
#include "line_buffers.glsl"

flat out uint vSegmentIn;

void main() {
    vSegmentIn = segmentOfSlot(uint(gl_VertexID));
    gl_Position = vec4(0.0);
}
