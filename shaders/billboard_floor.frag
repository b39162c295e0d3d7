// The cost floor of the line fragment shaders (tests/bench/raster_floor_bench.cpp): every
// fragment of a segment's billboard writes one constant colour. No varying is read, so the linker
// drops the vertex stage's per-segment outputs: what is left is pulling the billboard corners,
// rasterizing the quads and writing their fragments.
layout(location = 0) out vec4 outColor;

void main() {
    outColor = vec4(0.85, 0.55, 0.25, 1.0);
}
