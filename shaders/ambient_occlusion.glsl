// Cone traced ambient occlusion at a shaded point, with the parameters gl::AmbientOcclusion sets.
// GLSL 4.50 chunk. Without AMBIENT_OCCLUSION it is 1 (unoccluded). With AO_LINE_CACHE too,
// lineAmbientOcclusion reads the per-segment cache of shaders/ao_line_cache.glsl instead.
#ifdef AMBIENT_OCCLUSION
#include "cone_tracing.glsl"
#ifdef AO_LINE_CACHE
#include "ao_line_cache.glsl"
#endif
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

// AO of a point on line segment `segment` (rasterized line paths): cached when the program is
// compiled with AO_LINE_CACHE (render.ao.cache "segments"), else cone traced here.
float lineAmbientOcclusion(uint segment, vec3 position, vec3 normal) {
#if defined(AMBIENT_OCCLUSION) && defined(AO_LINE_CACHE)
    return cachedLineOcclusion(segment, position, normalize(normal));
#else
    return ambientOcclusion(position, normal);
#endif
}
