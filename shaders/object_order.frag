// Object-order transparency: every fragment blended in the order the sorted segments are drawn,
// with the "under" operator (glBlendFunc(ONE_MINUS_DST_ALPHA, ONE) on premultiplied colour) —
// the baseline the k-buffer improves on.
#include "transparent_fragment.glsl"

layout(location = 0) out vec4 outColor;

void main() {
    LineFragment f;
    if (!lineFragment(f)) discard;
    outColor = vec4(f.color.rgb * f.color.a, f.color.a);
}
