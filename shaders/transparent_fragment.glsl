// One transparent fragment of a segment: the ray-cast entry into its rounded cone after cap
// clipping (core/cap_clipping.h has the rule; core/transparent_reference.cpp is the CPU twin),
// shaded with Blinn-Phong, with the vertex alpha interpolated along the segment. Shared by the
// object-order, k-buffer and depth-peeling fragment shaders. GLSL 4.50 chunk, #include'd before
// any other chunk: the frame's camera and light come from flat varyings (frame_uniforms.glsl).
#define FRAME_VARYINGS_IN
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "cap_clipping.glsl"
#include "shading.glsl"
#include "line_buffers.glsl"
#include "frame_uniforms.glsl"
#include "ambient_occlusion.glsl"
#include "hierarchical_culling.glsl"
#include "segment_varyings.glsl"

flat in uint vSegment;

struct LineFragment {
    float depth;  // view-space depth, > 0
    vec4 color;   // shaded linear RGB, straight alpha
    vec3 normal;  // outward world normal
};

#ifdef HALO
// Depth-dependent halos (Everts et al. 2009), with which Günther, Rössl & Theisel 2013 (Sect. 4.2)
// draw their lines: a ring HALO_WIDTH tube radii wide around the tube's silhouette, in HALO_COLOR
// (linear RGB) with the line's alpha. Its depth grows linearly across the ring, from the axis
// depth at the silhouette (u = 0) to HALO_DEPTH radii behind it at the outer edge (u = 1), as the
// paper's strips push their halo region back: a line further behind than that is hidden by the
// whole ring, one at about the same depth (a bundle) shows through it. The ring belongs to the
// segment whose grown cone the ray enters on its surface after cap clipping, like a tube entry.
// core/halo.h is the CPU twin (the reference and the Embree path); keep them in lock-step.
bool haloFragment(Ray ray, vec4 plane0, vec4 plane1, bool clip0, bool clip1, out LineFragment f) {
    RoundedCone c = varyingCone();
    const float scale = 1.0 + HALO_WIDTH;
    RoundedCone outer = RoundedCone(c.x0, c.r0 * scale, c.x1, c.r1 * scale);
    ConeInterval ring = intersectRoundedCone(ray, outer, vAxis);  // the same axis
    float tEntry;
    vec3 nEntry;
    if (!segmentFragment(ray, ring, plane0, plane1, clip0, clip1, tEntry, nEntry)) return false;
    // The ray's closest approach to the axis: the middle of its chord through the grown cone
    // (exact for a cylinder and for the end spheres).
    vec3 mid = ray.origin + 0.5 * (ring.tIn + ring.tOut) * ray.dir;
    vec3 axis = c.x1 - c.x0;
    float len2 = dot(axis, axis);
    float s = len2 > 0.0 ? clamp(dot(mid - c.x0, axis) / len2, 0.0, 1.0) : 0.0;
    vec3 q = c.x0 + s * axis;
    float radius = mix(c.r0, c.r1, s);
    float u = (distance(mid, q) - radius) / (HALO_WIDTH * radius);
    // Within the tube's radius but not this segment's surface: a neighbour's at a joint.
    if (!(u >= 0.0)) return false;
    f.depth = dot(q - uEye, uForward) + min(u, 1.0) * HALO_DEPTH * radius;
    if (!(f.depth > 0.0)) return false;
#ifdef REGION_CLIP
    if (!inRegion(ray.origin + tEntry * ray.dir)) return false;
#endif
    f.color = vec4(HALO_COLOR, mix(vColor0.a, vColor1.a, s));
    f.normal = nEntry;
    return true;
}
#endif

#ifdef CULLING
// Depth slices: a pixel already (nearly) opaque has depth 0 (shaders/cull_mark.frag), and the
// fragments there fail the depth test before the shader runs (gl/hierarchical_culling.h).
layout(early_fragment_tests) in;
#endif

bool lineFragment(out LineFragment f) {
    // The segment's cone, cap planes (uCapClipping) and colours: segment_varyings.glsl.
    vec4 a = vConeA, b = vConeB;
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    ConeInterval cone = intersectRoundedCone(ray, varyingCone(), vAxis);
    bool clip0 = vClip0 != vec4(0.0), clip1 = vClip1 != vec4(0.0);
    vec4 plane0 = vClip0, plane1 = vClip1;
    float t;
    vec3 n;
    if (!segmentFragment(ray, cone, plane0, plane1, clip0, clip1, t, n)) {
#ifdef HALO
        return haloFragment(ray, plane0, plane1, clip0, clip1, f);
#else
        return false;
#endif
    }
    f.depth = viewDepth(ray, t);
    if (!(f.depth > 0.0)) return false;
    vec3 p = ray.origin + t * ray.dir;
#ifdef REGION_CLIP
    // The entry lies in another region, which blends it (core/region.h).
    if (!inRegion(p)) return false;
#endif
    vec3 axis = b.xyz - a.xyz;
    float len2 = dot(axis, axis);
    float s = len2 > 0.0 ? clamp(dot(p - a.xyz, axis) / len2, 0.0, 1.0) : 0.0;
    vec4 albedo = mix(vColor0, vColor1, s);
    // Per fragment before insertion (the paper's cost model for the transparent path).
    albedo.rgb *= lineAmbientOcclusion(vSegment, a.xyz, b.xyz, p, dot(n, ray.dir) <= 0.0 ? n : -n);
    f.color = vec4(shadeBlinnPhong(albedo.rgb, n, ray.dir, uLightDir, uLightTerms.x, uLightTerms.y, uLightTerms.z,
                                   uLightTerms.w),
                   albedo.a);
    // Shaded colour is clamped to [0, 1] in every transparent path: the k-buffer stores RGBA8, and
    // the references must blend the same values (core/transparent_reference.cpp does too).
    f.color.rgb = clamp(f.color.rgb, 0.0, 1.0);
    f.normal = n;
    return true;
}
