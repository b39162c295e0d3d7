// Visibility pass of the opaque path: ray-cast the segment's rounded cone, write the true depth
// and the segment id, nothing else. Everything else about the visible surface is recovered once
// per pixel by surface_attributes.frag (a visibility buffer): on llvmpipe every render target
// written per fragment costs, and most fragments are overdrawn.
#define FRAME_VARYINGS_IN  // the frame's camera from flat varyings (frame_uniforms.glsl)
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "line_buffers.glsl"
#include "frame_uniforms.glsl"
#include "visible_hit.glsl"
#include "hierarchical_culling.glsl"
#include "segment_varyings.glsl"

flat in uint vSegment;

layout(location = 0) out uint outSegment;

void main() {
#ifdef CULL_FRAGMENT_TEST
    // Depth slices: skip the intersection where earlier slices already cover this pixel nearer
    // than anything of this segment (not on llvmpipe, gl/hierarchical_culling.h).
    if (cullFragment(ivec2(gl_FragCoord.xy), cullNearestDepth(vConeA, vConeB))) discard;
#endif
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    float t, fragDepth;
    vec3 n;
    if (!visibleFragmentDepth(ray, varyingCone(), vAxis, t, n, fragDepth)) discard;
#ifdef REGION_CLIP
    // This segment's visible point belongs to another region: the nearest one in this region wins
    // the depth test, so the regions' depth images Z-composite to the whole frame's first hit.
    if (!inRegion(ray.origin + t * ray.dir)) discard;
#endif
    // GL_LESS keeps the first of equal depths, so which segment id survives a tie depends on the
    // draw order; surface_attributes.frag resolves ties independently of it.
    outSegment = vSegment;
    gl_FragDepth = fragDepth;
}
