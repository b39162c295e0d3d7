// Early-z approximation of Staib et al. 2015, Sect. 5.2: after a chunk of sorted particles, pixels
// whose accumulated alpha exceeds the threshold get depth 0, so the depth test (early fragment
// tests in sphere.frag) rejects every later particle fragment there before it is shaded. Reads the
// colour target the particles blend into (after glTextureBarrier), writes depth only.
layout(binding = TEXTURE_EARLY_Z_ACCUMULATED) uniform sampler2D uAccumulated;
uniform float uThreshold;

void main() {
    if (texelFetch(uAccumulated, ivec2(gl_FragCoord.xy), 0).a <= uThreshold) discard;
    gl_FragDepth = 0.0;
}
