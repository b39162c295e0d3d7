// Vertex pulling: 6 vertices (two triangles) per segment, each invocation builds its segment's
// billboard (Groß & Gumhold 2020, Sect. 5.1) from the SSBOs and emits one corner. Measured on
// llvmpipe to beat a geometry shader (docs/performance.md).
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "billboard.glsl"
#include "line_buffers.glsl"

uniform mat4 uViewProj;
uniform vec3 uEye;
uniform vec3 uForward;
uniform bool uOrthographic;

flat out uint vSegment;

// Two triangles of the quad from its 4 corners in triangle-strip order.
const int kCorner[6] = int[6](0, 1, 2, 2, 1, 3);

void main() {
    uint segment = uint(gl_VertexID) / 6u;
    int corner = kCorner[gl_VertexID % 6];
    uint v0 = segmentVertices[2u * segment];
    uint v1 = segmentVertices[2u * segment + 1u];
    vec4 a = positionRadius[v0];
    vec4 b = positionRadius[v1];
    RoundedCone cone = RoundedCone(a.xyz, a.w, b.xyz, b.w);
    vec2 corners[4];
    computeBillboard(cone, uViewProj, uEye, uForward, uOrthographic, corners);
    vSegment = segment;
    gl_Position = vec4(corners[corner], 0.0, 1.0);
}
