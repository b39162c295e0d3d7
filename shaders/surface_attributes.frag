// Once per pixel after the visibility pass: re-intersect the ray with the visible segment (the
// same function on the same inputs, so the same hit), settle depth ties by segment index, and
// write linear albedo, outward world normal + view depth, and polyline id for shading and the
// AOVs.
// The camera from flat varyings (fullscreen.vert with FULLSCREEN_FRAME_VARYINGS).
#define FRAME_VARYINGS_IN
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "line_buffers.glsl"
#include "frame_uniforms.glsl"
#include "visible_hit.glsl"

layout(binding = TEXTURE_VISIBILITY_SEGMENTS) uniform usampler2D uSegments;

const uint kNoSegment = 0xFFFFFFFFu;

layout(location = 0) out vec4 outAlbedo;       // linear RGB, straight alpha
layout(location = 1) out vec4 outNormalDepth;  // outward world normal, view depth (+inf: background)
layout(location = 2) out uint outId;           // polyline id

// Depth ties go to the lower segment index, whatever order the visibility pass drew in.
// Its depth test (GL_LESS) keeps the first drawn of equal gl_FragDepth values. Unsorted, segments
// are drawn by index, so the lower index wins; with culling they are drawn front to back in depth
// slices (Groß & Gumhold 2020, Sect. 4.1 and 4.3), and a polyline's later segment often comes
// before its predecessor. Ties are common exactly there: the joint sphere the two rounded cones
// share touches each one's lateral surface tangentially (both take the joint vertex's radius), so
// near that circle the sphere of one segment and the lateral surface of the other lie at depths
// equal to second order in the distance from it, which round to the same float over a band of
// pixels, while their normals differ to first order (by up to 0.03 on the 1M-segment tornado at
// 1920x1080, 1-2/255 after shading). Keeping the depth-test winner made culling change those
// pixels; instead walk down to the lowest predecessor the depth test would have kept had it been
// drawn first, i.e. whose fragment depth, computed as the visibility pass computes it, is <= the
// winner's. Unsorted, that is the winner itself (images unchanged); sorted, the walk finds the
// same segment from whichever member of the tie won. The CPU reference (core/cpu_reference.h) and
// the ray tracer (rt/raytraced_renderer.h) apply the same rule. Only polyline neighbours are
// compared: other segments meet at equal depth only where their surfaces cross, in a band about
// one float step wide, not along a tangential contact.
// The walk returns `best`, not its loop counter: on llvmpipe (Mesa 22.3) a loop that decremented
// `segment` itself while its condition read segmentVertices[2u * segment] made the same read after
// the loop return 0 in lanes that had left the loop before the others (polyline id 0 next to
// walked pixels); with the condition reading other indices the ids were right, so the read after
// the loop seems to reuse the condition's, made while those lanes were masked off.
uint lowestTiedSegment(Ray ray, uint segment, inout float t, inout vec3 n, float fragDepth) {
    uint best = segment;
    for (uint s = segment; s > 0u; --s) {
        // Segments of a polyline are consecutive and share their joint vertex.
        if (segmentVertices[2u * s - 1u] != segmentVertices[2u * s]) break;
        float tPrev, depthPrev;
        vec3 nPrev;
        if (!visibleFragmentDepth(ray, segmentCone(s - 1u), tPrev, nPrev, depthPrev) || depthPrev > fragDepth) break;
#ifdef REGION_CLIP
        // A tied predecessor whose hit lies in another region is that region's (as in the
        // visibility pass, rounded_cone_gbuffer.frag).
        if (!inRegion(ray.origin + tPrev * ray.dir)) break;
#endif
        best = s - 1u;
        t = tPrev;
        n = nPrev;
        fragDepth = depthPrev;
    }
    return best;
}

void main() {
    uint segment = texelFetch(uSegments, ivec2(gl_FragCoord.xy), 0).r;
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    float t, fragDepth;
    vec3 n;
    if (segment == kNoSegment || !visibleFragmentDepth(ray, segmentCone(segment), t, n, fragDepth)) {
        outAlbedo = vec4(0.0);
        outNormalDepth = vec4(0.0, 0.0, 0.0, uintBitsToFloat(0x7F800000u));
        outId = kNoSegment;
        return;
    }
    segment = lowestTiedSegment(ray, segment, t, n, fragDepth);
    uint v0 = segmentVertices[2u * segment];
    uint v1 = segmentVertices[2u * segment + 1u];
    vec3 a = positionRadius[v0].xyz, b = positionRadius[v1].xyz;
    vec3 p = ray.origin + t * ray.dir;
    vec3 axis = b - a;
    float len2 = dot(axis, axis);
    float s = len2 > 0.0 ? clamp(dot(p - a, axis) / len2, 0.0, 1.0) : 0.0;
    outAlbedo = mix(vertexColor[v0], vertexColor[v1], s);
    outNormalDepth = vec4(n, viewDepth(ray, t));
    outId = polylineId[v0];
}
