// Ambient occlusion A_O (Eq. 2) and coloured ambient light L_A (Eq. 7) of sphere glyphs by voxel
// cone tracing (Staib et al. 2015, Sect. 3) over the RGBA sphere volume of gl/sphere_ambient.h
// (premultiplied colour, alpha = coverage x opacity), with the cone set, tangent frame and step
// rule of cone_tracing.glsl: steps one cone diameter long, sampled at their middle at the mip
// level of that diameter, opacity per step 1 - (1 - a)^(strength d / voxel), front to back. L_A
// gathers the volume's colour (rgb / a) weighted like a front-to-back composite along each cone:
// the light that neighbouring particles reflect toward the shaded point.
#include "cone_tracing.glsl"

uniform sampler3D uSphereVolume;
uniform vec3 uSphereVolumeOrigin;
uniform float uSphereVolumeVoxel;
uniform ivec3 uSphereVolumeSize;
uniform int uSphereVolumeLevels;
uniform int uAoCones;
uniform float uAoAperture;  // radians, full apex angle
uniform float uAoDistance;  // world units
uniform float uAoStrength;
uniform float uAoStartOffset;  // world units beyond the surface

vec4 sphereVolumeSample(vec3 p, float lod) {
    vec3 uvw = (p - uSphereVolumeOrigin) / (uSphereVolumeVoxel * vec3(uSphereVolumeSize));
    return textureLod(uSphereVolume, uvw, lod);
}

// Occlusion and gathered colour of one cone.
void traceSphereCone(vec3 apex, vec3 dir, float tanHalf, out float occlusion, out vec3 light) {
    float maxLod = float(max(uSphereVolumeLevels - 1, 0));
    occlusion = 0.0;
    light = vec3(0.0);
    float t = uAoStartOffset;
    for (int i = 0; i < 128 && t < uAoDistance && occlusion <= 0.99; ++i) {
        float diameter = max(2.0 * t * tanHalf, uSphereVolumeVoxel);
        float stepLength = min(diameter, uAoDistance - t);
        float lod = clamp(log2(diameter / uSphereVolumeVoxel), 0.0, maxLod);
        vec4 s = sphereVolumeSample(apex + (t + 0.5 * stepLength) * dir, lod);
        float a = clamp(s.a, 0.0, 1.0);
        float alpha = 1.0 - exp2(uAoStrength * stepLength / uSphereVolumeVoxel * log2(max(1.0 - a, 1e-30)));
        vec3 color = s.a > 1e-6 ? clamp(s.rgb / s.a, 0.0, 1.0) : vec3(0.0);
        light += (1.0 - occlusion) * alpha * color;
        occlusion += (1.0 - occlusion) * alpha;
        t += stepLength;
    }
}

// At surface point p with outward unit normal n: ao = 1 unoccluded .. 0, ambientLight = L_A.
void sphereAmbient(vec3 p, vec3 n, out float ao, out vec3 ambientLight) {
    vec3 tangent, bitangent;
    coneTangentFrame(n, tangent, bitangent);
    float tanHalf = tan(0.5 * uAoAperture);
    bool central = uAoCones == 1 || uAoCones >= 6;
    int ringCones = central ? uAoCones - 1 : uAoCones;
    float ringPolar = uAoCones >= 6 ? radians(60.0) : radians(45.0);
    float ringCos = cos(ringPolar), ringSin = sin(ringPolar);
    float visible = 0.0, weightSum = 0.0;
    ambientLight = vec3(0.0);
    float occ;
    vec3 light;
    if (central) {
        traceSphereCone(p, n, tanHalf, occ, light);
        visible += 1.0 - occ;
        ambientLight += light;
        weightSum += 1.0;
    }
    for (int i = 0; i < ringCones; ++i) {
        float phi = 6.28318530718 * float(i) / float(ringCones);
        vec3 dir = ringCos * n + ringSin * (cos(phi) * tangent + sin(phi) * bitangent);
        traceSphereCone(p, dir, tanHalf, occ, light);
        visible += ringCos * (1.0 - occ);
        ambientLight += ringCos * light;
        weightSum += ringCos;
    }
    ao = visible / weightSum;
    ambientLight /= weightSum;
}

#ifdef AMBIENT_CACHE
// The cached ambient cube of one sphere (sphere_ambient_cache.comp; SSBO_SPHERE_AMBIENT_CUBE, six packed unorm
// RGBA8 per sphere: +x, -x, +y, -y, +z, -z), passed from the vertex shader as flat varyings:
// `positive` = faces +x, +y, +z, `negative` = -x, -y, -z. Faces weighted by n^2 (the weights sum
// to 1), so an axis-aligned normal gets exactly the traced value.
void sphereAmbientCached(uvec3 positive, uvec3 negative, vec3 n, out float ao, out vec3 ambientLight) {
    vec3 w = n * n;
    vec4 v = w.x * unpackUnorm4x8(n.x < 0.0 ? negative.x : positive.x) +
             w.y * unpackUnorm4x8(n.y < 0.0 ? negative.y : positive.y) +
             w.z * unpackUnorm4x8(n.z < 0.0 ? negative.z : positive.z);
    ao = v.a;
    ambientLight = v.rgb;
}
#endif
