// Opacity optimization, pass 2: blends each pixel's fragment list front to back with the
// optimised opacities, alpha = style alpha * lerp(a_i, a_i+1, frac(w)) (Günther, Rössl & Theisel
// 2013, Sect. 5), premultiplied, and empties the list for the next frame. The lists arrive sorted:
// gl/opacity_renderer.cpp sorts them on the CPU for Algorithm 1 anyway and uploads the sorted
// links, so this pass only walks them.
#define OPACITY_RESOLVE
#include "opacity_common.glsl"

layout(std430, binding = 15) readonly buffer PartOpacity { float partOpacity[]; };

layout(location = 0) out vec4 outColor;

void main() {
    uint pixel = pixelIndex(ivec2(gl_FragCoord.xy));
    vec4 sum = vec4(0.0);
    for (uint n = listHead[pixel]; n != kEndOfList; n = fragmentNext[n]) {
        FragmentNode f = fragmentNode[n];
        vec4 c = unpackUnorm4x8(f.color);
        float a = partOpacity[f.part];
        if (f.frac > 0.0) a = mix(a, partOpacity[f.part + 1u], f.frac);
        c.a *= a;
        sum += (1.0 - sum.a) * vec4(c.rgb * c.a, c.a);
        if (sum.a >= 1.0) break;  // nothing behind can show
    }
    listHead[pixel] = kEndOfList;
    outColor = sum;
}
