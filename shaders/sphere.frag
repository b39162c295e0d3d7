// Sphere glyphs (Staib, Grottel & Gumhold 2015): one ray-sphere interval per fragment.
//   default: the density model's analytic opacity of the interval (Sect. 4) and the emission of
//            Eq. 2 / 7, premultiplied, blended "under" (front to back) in the power-distance order
//            of the sort; EARLY_Z adds early fragment tests against the chunk mask (Sect. 5.2).
//   OPAQUE:  the first hit with gl_FragDepth (depth test), plain Blinn-Phong surface, plus the
//            world normal / view depth and the particle id for the AOVs.
// The frame's camera and light come from flat varyings (frame_uniforms.glsl).
#define FRAME_VARYINGS_IN
#include "camera.glsl"
#include "frame_uniforms.glsl"
#include "shading.glsl"
#include "sphere_glyph.glsl"
#ifdef AMBIENT_OCCLUSION
#include "sphere_ambient.glsl"
#endif

#ifdef EARLY_Z
layout(early_fragment_tests) in;
#endif


uniform int uDensityModel;  // kDensity*
uniform float uInnerRatio;
uniform float uNormalisation;  // P of the density model
uniform float uAlphaRv;
uniform float uAlphaA;

// The particle (shaders/sphere_billboard.vert).
flat in vec4 vCenterRadius;
flat in vec4 vColor;
flat in uint vId;
#ifdef AMBIENT_CACHE
flat in uvec3 vAmbientPositive;
flat in uvec3 vAmbientNegative;
#endif

layout(location = 0) out vec4 outColor;
#ifdef OPAQUE
layout(location = 1) out vec4 outNormalDepth;
layout(location = 2) out uint outId;
#endif

void main() {
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    vec4 cr = vCenterRadius;
    SphereInterval s = intersectSphere(ray.origin, ray.dir, cr.xyz, cr.w);
    if (!s.hit) discard;
    vec4 base = vColor;
    vec3 p = ray.origin + s.tNear * ray.dir;
#ifdef REGION_CLIP
    // The sphere's entry point (the eye, when the eye is inside it) lies in another region.
    if (!inRegion(p)) discard;
#endif
    vec3 n = (p - cr.xyz) / cr.w;
    float ao = 1.0;
    vec3 ambientLight = vec3(0.0);
#if defined(AMBIENT_CACHE)
    sphereAmbientCached(vAmbientPositive, vAmbientNegative, n, ao, ambientLight);
#elif defined(AMBIENT_OCCLUSION)
    sphereAmbient(p, n, ao, ambientLight);
#endif
#ifdef OPAQUE
    float depth = viewDepth(ray, s.tNear);
    gl_FragDepth = depth / uFarDepth;
    vec3 e = sphereEmission(base.rgb, n, ray.dir, uLightDir, uLightTerms, 0.0, uAlphaA, ao, ambientLight);
    outColor = vec4(e, 1.0);
    outNormalDepth = vec4(n, depth);
    outId = vId;
#else
    float alpha = sphereOpacity(base.a, unitOpticalDepth(uDensityModel, uInnerRatio, s, cr.w), uNormalisation);
    if (alpha <= 0.0) discard;
    vec3 e = sphereEmission(base.rgb, n, ray.dir, uLightDir, uLightTerms, uAlphaRv, uAlphaA, ao, ambientLight);
    outColor = vec4(e * alpha, alpha);
#endif
}
