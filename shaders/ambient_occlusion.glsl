// Cone traced ambient occlusion at a shaded point, with the parameters gl::AmbientOcclusion sets.
// GLSL 4.50 chunk. Without AMBIENT_OCCLUSION it is 1 (unoccluded).
#ifdef AMBIENT_OCCLUSION
#include "cone_tracing.glsl"
uniform int uAoCones;
uniform float uAoAperture;     // full apex angle, radians
uniform float uAoDistance;     // world units
uniform float uAoStrength;
uniform float uAoStartOffset;  // world units
#endif

// normal: the surface normal facing the viewer (the hemisphere the cones look into).
float ambientOcclusion(vec3 position, vec3 normal) {
#ifdef AMBIENT_OCCLUSION
    return coneTracedOcclusion(position, normal, uAoCones, uAoAperture, uAoDistance, uAoStrength, uAoStartOffset);
#else
    return 1.0;
#endif
}
