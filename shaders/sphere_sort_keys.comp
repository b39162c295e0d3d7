// Visibility-sort keys of sphere glyphs (Staib et al. 2015): the order-preserving uint key
// (sort_keys.glsl) of the power distance |c - e|^2 - r^2 (perspective; negative inside a sphere)
// or of the centre's view depth (orthographic), and the particle index as the sorted value.
// The GPU twin of tc::sphereSortKey.
layout(local_size_x = 64) in;

layout(std430, binding = SSBO_SPHERE_CENTER_RADIUS) readonly buffer CenterRadius { vec4 centerRadius[]; };
layout(std430, binding = SSBO_SPHERE_SORT_KEYS) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = SSBO_SPHERE_SORT_VALUES) writeonly buffer Values { uint values[]; };

#include "sort_keys.glsl"
#include "frame_uniforms.glsl"

uniform uint uFirst;
uniform uint uCount;

void main() {
    uint i = uFirst + gl_GlobalInvocationID.x;
    if (i >= uCount) return;
    vec4 cr = centerRadius[i];
    vec3 d = cr.xyz - uEye;
    float key = uOrthographic ? dot(d, uForward) : dot(d, d) - cr.w * cr.w;
    keys[i] = sortKeyFromFloat(key);
    values[i] = i;
}
