// Cone traced ambient occlusion at a shaded point, with the parameters gl::AmbientOcclusion sets.
// GLSL 4.50 chunk. Without AMBIENT_OCCLUSION it is 1 (unoccluded). Programs shading lines add
// AO_LINES (gl::AmbientOcclusion::lineDefines): lineAmbientOcclusion then excludes the shaded
// segment's own tube (shaders/cone_tracing.glsl, "Self-occlusion"); with AO_LINE_CACHE too it
// reads the per-segment cache of shaders/ao_line_cache.glsl instead.
#ifdef AMBIENT_OCCLUSION
#include "cone_tracing.glsl"
#ifdef AO_LINES
#include "line_buffers.glsl"
#endif
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

#ifdef AMBIENT_OCCLUSION
// AO at a point of tube `own` (cone_tracing.glsl's ConeOwnTube).
float tubeAmbientOcclusion(vec3 position, vec3 normal, ConeOwnTube own) {
    return coneTracedTubeOcclusion(position, normal, own, uAoCones, uAoAperture, uAoDistance, uAoStrength,
                                   uAoStartOffset);
}
#endif

#if defined(AMBIENT_OCCLUSION) && defined(AO_LINES)
// Cone traced AO of a point on segment `segment` of the uploaded line set (line_buffers.glsl).
float exactLineAmbientOcclusion(uint segment, vec3 position, vec3 normal) {
    uint ia = segmentVertices[2u * segment], ib = segmentVertices[2u * segment + 1u];
    return tubeAmbientOcclusion(position, normal,
                                coneOwnTube(positionRadius[ia], positionRadius[ib], vertexColor[ia].a, vertexColor[ib].a));
}
#endif

// AO of a point on line segment `segment` from a to b (rasterized line paths): cached when the
// program is compiled with AO_LINE_CACHE (render.ao.cache "precomputed"), else cone traced here.
// The line fragment shaders pass the ends from their flat varyings: on llvmpipe each storage
// buffer read of a fragment shader is a scalar load per lane.
float lineAmbientOcclusion(uint segment, vec3 a, vec3 b, vec3 position, vec3 normal) {
#if defined(AMBIENT_OCCLUSION) && defined(AO_LINE_CACHE)
    return cachedLineOcclusion(segment, a, b, position, normalize(normal));
#elif defined(AMBIENT_OCCLUSION) && defined(AO_LINES)
    return exactLineAmbientOcclusion(segment, position, normal);
#else
    return ambientOcclusion(position, normal);
#endif
}

// The same for passes without the segment's varyings (full screen): the cache's ends from the
// line buffers.
float lineAmbientOcclusion(uint segment, vec3 position, vec3 normal) {
#if defined(AMBIENT_OCCLUSION) && defined(AO_LINE_CACHE)
    vec3 a = positionRadius[segmentVertices[2u * segment]].xyz;
    vec3 b = positionRadius[segmentVertices[2u * segment + 1u]].xyz;
    return lineAmbientOcclusion(segment, a, b, position, normal);
#else
    return lineAmbientOcclusion(segment, vec3(0.0), vec3(0.0), position, normal);
#endif
}
