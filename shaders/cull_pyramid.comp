// One level of the culling pyramid (shaders/hierarchical_culling.glsl): each texel reduces the
// texels of the level below it — 2 x 2, plus the leftover row / column of an odd size at the last
// texel — with max (CULL_MAX_DEPTH) or min (CULL_MIN_OPACITY).
// FROM_SOURCE: level 1 straight from the render target: the depth buffer (linear view depth /
// uFarDepth, scaled back to view depth) or the accumulation target's alpha. Otherwise from the
// previous pyramid level.
layout(local_size_x = 8, local_size_y = 8) in;

#ifdef FROM_SOURCE
layout(binding = TEXTURE_CULL_SOURCE) uniform sampler2D uSource;
uniform float uFarDepth;
#else
uniform int uSourceOffset;  // the previous level in the buffer
uniform ivec2 uSourceSize;
#endif
layout(std430, binding = SSBO_CULL_PYRAMID) buffer CullPyramid { float cullPyramid[]; };
uniform int uLevelOffset;
uniform ivec2 uLevelSize;

float fetchSource(ivec2 p) {
#ifdef FROM_SOURCE
#ifdef CULL_MAX_DEPTH
    return texelFetch(uSource, p, 0).r * uFarDepth;
#else
    return texelFetch(uSource, p, 0).a;
#endif
#else
    return cullPyramid[uSourceOffset + p.y * uSourceSize.x + p.x];
#endif
}

void main() {
    ivec2 size = uLevelSize;
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, size))) return;
#ifdef FROM_SOURCE
    ivec2 sourceSize = textureSize(uSource, 0);
#else
    ivec2 sourceSize = uSourceSize;
#endif
    ivec2 lo = 2 * t;
    ivec2 hi = min(mix(2 * t + 1, sourceSize - 1, equal(t, size - 1)), sourceSize - 1);
    float value = fetchSource(lo);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
#ifdef CULL_MAX_DEPTH
            value = max(value, fetchSource(ivec2(x, y)));
#else
            value = min(value, fetchSource(ivec2(x, y)));
#endif
        }
    cullPyramid[uLevelOffset + t.y * size.x + t.x] = value;
}
