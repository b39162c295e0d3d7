// One transparent fragment of a segment: the ray-cast entry into its rounded cone after cap
// clipping (core/cap_clipping.h has the rule; core/transparent_reference.cpp is the CPU twin),
// shaded with Blinn-Phong, with the vertex alpha interpolated along the segment. Shared by the
// object-order, k-buffer and depth-peeling fragment shaders. GLSL 4.50 chunk.
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

bool lineFragment(out LineFragment f) {
#ifdef CULLING
    // Depth slices: this pixel is already (nearly) opaque; skip the ray casting and shading.
    if (cullFragment(ivec2(gl_FragCoord.xy), 0.0)) return false;
#endif
    // The segment's cone, cap planes (uCapClipping) and colours: segment_varyings.glsl.
    vec4 a = vConeA, b = vConeB;
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    ConeInterval cone = intersectRoundedCone(ray, varyingCone());
    bool clip0 = vClip0 != vec4(0.0), clip1 = vClip1 != vec4(0.0);
    vec4 plane0 = vClip0, plane1 = vClip1;
    float t;
    vec3 n;
    if (!segmentFragment(ray, cone, plane0, plane1, clip0, clip1, t, n)) return false;
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
    albedo.rgb *= lineAmbientOcclusion(vSegment, p, dot(n, ray.dir) <= 0.0 ? n : -n);
    f.color = vec4(shadeBlinnPhong(albedo.rgb, n, ray.dir, uLightDir, uLightTerms.x, uLightTerms.y, uLightTerms.z,
                                   uLightTerms.w),
                   albedo.a);
    // Shaded colour is clamped to [0, 1] in every transparent path: the k-buffer stores RGBA8, and
    // the references must blend the same values (core/transparent_reference.cpp does too).
    f.color.rgb = clamp(f.color.rgb, 0.0, 1.0);
    f.normal = n;
    return true;
}
