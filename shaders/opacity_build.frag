// Opacity optimization, pass 1: every fragment of every rounded cone (the transparent path's
// fragments, shaders/transparent_fragment.glsl) goes into its pixel's list with its w. The lists
// are unordered; the CPU sorts them to build h_ij and to blend them.
// Writes colour 0 with blending on: llvmpipe may drop side effects of covered primitives when
// blending is off.
#include "transparent_fragment.glsl"
#include "opacity_common.glsl"

uniform uint uPartsPerLine;

layout(location = 0) out vec4 outColor;

void main() {
    outColor = vec4(0.0);
    LineFragment f;
    if (!lineFragment(f)) discard;
    // The hit's position along the segment, from its depth (lineFragment keeps it to itself).
    uint v0 = segmentVertices[2u * vSegment];
    uint v1 = segmentVertices[2u * vSegment + 1u];
    vec3 a = vConeA.xyz, b = vConeB.xyz;  // the ends from the flat varyings, not two more buffer reads
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    float t = uOrthographic ? f.depth : f.depth / dot(ray.dir, uForward);
    vec3 p = ray.origin + t * ray.dir;
    vec3 axis = b - a;
    float len2 = dot(axis, axis);
    float s = len2 > 0.0 ? clamp(dot(p - a, axis) / len2, 0.0, 1.0) : 0.0;
    float w = mix(vertexPartW[v0].localW, vertexPartW[v1].localW, s);
    float whole = min(floor(w), float(uPartsPerLine - 1u));
    float frac = whole >= float(uPartsPerLine - 1u) ? 0.0 : clamp(w - whole, 0.0, 1.0);

    uint node = atomicAdd(fragmentCount, 1u);
    if (node >= uCapacity) discard;  // counted, not stored: the renderer reports the overflow
    fragmentDepth[node] = f.depth;
    fragmentPart[node] = vertexPartW[v0].firstPart + uint(whole);
    fragmentFrac[node] = frac;
    fragmentColor[node] = packUnorm4x8(f.color);
    fragmentNext[node] = atomicExchange(listHead[pixelIndex(ivec2(gl_FragCoord.xy))], node);
}
