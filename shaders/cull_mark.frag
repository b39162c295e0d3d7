// Depth slices, transparent lines (Groß & Gumhold 2020, Sect. 4.3): after a slice, gives every
// pixel that the per-fragment culling test hides (hierarchical_culling.glsl cullFragment: the
// accumulated opacity of its level-1 texel exceeds the threshold) depth 0. The later slices' line
// fragments lie at depth 0.5 and are tested before their shader runs (early_fragment_tests in
// transparent_fragment.glsl), so there they fail without being shaded: on llvmpipe the depth
// test is what skips a 4x4 block's shader, where a discard inside it does not
// (gl/hierarchical_culling.h). Drawn with colour writes off, depth test ALWAYS.
#include "hierarchical_culling.glsl"

void main() {
    if (!cullFragment(ivec2(gl_FragCoord.xy), 0.0)) discard;
    gl_FragDepth = 0.0;
}
