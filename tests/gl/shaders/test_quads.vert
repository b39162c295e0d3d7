// tests/gl/quad_indices_test.cpp: quad q covers the 2x2 pixel block (2 (q % uQuadsPerRow),
// 2 (q / uQuadsPerRow)) of the target, its corner positions taken from quad_corners.glsl's corner
// bits; the flat output is q where the shader takes the corner for the provoking one and a marker
// elsewhere, so a pattern whose provoking vertex is another corner shows the marker.
#include "quad_corners.glsl"

uniform uint uQuadsPerRow;
uniform vec2 uTargetSize;

flat out uint vQuad;

void main() {
    uint q = quadOfVertex();
    int corner = quadCorner();
    vec2 block = 2.0 * vec2(q % uQuadsPerRow, q / uQuadsPerRow);
    vec2 pixel = block + 2.0 * vec2(corner & 1, corner >> 1);
    gl_Position = vec4(2.0 * pixel / uTargetSize - 1.0, 0.0, 1.0);
    vQuad = isProvokingCorner(corner) ? q : 0xFFFFFFFEu;
}
