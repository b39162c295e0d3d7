// Level of detail for the voxel ray caster (render.vrc.lod; Kanzler, Rautenhaus & Westermann 2019,
// Sec. 3.4 and 5.1): from some point on, a ray stops intersecting tubes and marches the LoD volume
// (core/vrc_model.h, buildVrcLodVolume: Eq. 1's length x opacity per voxel weighted by each line's
// projected width, an extinction coefficient, with a colour), at ever coarser levels:
//   - footprint: where a voxel of level L covers at most uLodFootprint pixels, the ray samples
//     level L (the largest such L), so distant parts of the data are drawn from coarse levels;
//   - opacity acceleration (Sec. 5.1, after Danskin & Hanrahan): once the accumulated opacity
//     reaches uLodOpacityStart, every halving of the remaining transmittance moves the ray one
//     level up, and its step grows with the level's voxel size.
// The level only grows along a ray (t and the accumulated opacity only grow), so the ray leaves
// the exact tubes once, at a voxel boundary (vrcLodLevel >= 0 there), and marches the volume to
// the far side of the grid or to early ray termination. Included by vrc_raycast.comp with VRC_LOD;
// gl/vrc_renderer.cpp sets the uniforms. GLSL 4.50 chunk.
#ifndef TC_VRC_LOD_GLSL
#define TC_VRC_LOD_GLSL

const int kVrcLodMaxLevels = 12;  // VrcRenderer::kMaxLodLevels (resolution 1024 has 11)
// All levels in one 3D texture (GL_RGBA16F, trilinear), side by side along x, each with a border
// of one zero texel on every side: a sample near a level's edge blends with empty space, as it
// should, and never with the next level. The Eq. 1 levels are ceil(n / 2) per axis, which a
// mipmap chain of an odd-sized texture does not match.
layout(binding = TEXTURE_VRC_LOD) uniform sampler3D vrcLodAtlas;
uniform vec3 uLodAtlasInvSize;                // 1 / atlas size in texels
uniform float uLodAtlasX[kVrcLodMaxLevels];   // x texel of each level's first (border) texel
uniform int uLodLevels;
uniform float uLodFootprint;                  // 0: no switch by footprint
uniform float uLodOpacityStart;               // > 1: no opacity acceleration
uniform int uLodMinLevel;                     // 0; more: the coarsest levels only (benchmarks)

#ifdef VRC_LOD_STATS
// Samples taken at each level, and (last entry) rays that entered the LoD volume.
layout(std430, binding = SSBO_VRC_LOD_STATS) buffer VrcLodStats { uint vrcLodSamples[]; };
#endif

// World size of a pixel at distance t along a ray (the ray's own length, which exceeds the view
// depth off axis: the footprint errs toward finer levels).
float vrcPixelWorldSize(float t) {
    RayCamera cam = frameCamera();
    return cam.orthographic ? 2.0 * cam.orthoHalfHeight / cam.viewport.y : 2.0 * cam.tanHalfFovY * t / cam.viewport.y;
}

// The distance from which the footprint rule puts a ray into the volume (level 0 qualifies:
// uLodFootprint x pixel(t) >= uVoxelSize), 1e30 for never. The ray caster's loop compares t with
// it (and the opacity with uLodOpacityStart) at every voxel step: evaluating vrcLodLevel there
// made opaque frames that never switch 40 % slower on llvmpipe.
float vrcLodStartT() {
    if (uLodFootprint <= 0.0) return 1e30;
    RayCamera cam = frameCamera();
    if (cam.orthographic) return uLodFootprint * vrcPixelWorldSize(0.0) >= uVoxelSize ? 0.0 : 1e30;
    return uVoxelSize * cam.viewport.y / (uLodFootprint * 2.0 * cam.tanHalfFovY);
}

// The level a ray at t with accumulated opacity `a` samples, or -1: the exact tubes.
int vrcLodLevel(float t, float a) {
    int level = -1;
    if (uLodFootprint > 0.0) {
        // Voxels of level L are uVoxelSize * 2^L: the largest L with at most uLodFootprint pixels.
        float r = uLodFootprint * vrcPixelWorldSize(t) / uVoxelSize;
        if (r >= 1.0) level = int(floor(log2(r)));
    }
    if (a >= uLodOpacityStart) level = max(level, int(floor(log2((1.0 - uLodOpacityStart) / max(1.0 - a, 1e-6)))));
    return min(level, uLodLevels - 1);
}

// Mean Blinn-Phong of a tube of colour `base` seen across the ray (the LoD volume keeps no tangent):
// a tube whose axis is normal to the plane of the light and view directions, psi the angle between
// them. Its visible normals n(phi) = cos(phi) v + sin(phi) b, phi in [-pi/2, pi/2], cover the
// pixel width in proportion to cos(phi), so the mean diffuse term is
// (1/2) integral max(0, cos(phi - psi)) cos(phi) dphi = (sin(psi) + (pi - psi) cos(psi)) / 4
// (pi / 4 with the light at the eye), and the specular lobe around the half vector (at psi / 2)
// integrates to about cos(psi / 2) sqrt(pi / (2 shininess)) (Laplace's method).
vec3 vrcLodShade(vec3 base, vec3 dir) {
    float cosPsi = clamp(dot(uLightDir, -dir), -1.0, 1.0);
    float psi = acos(cosPsi);
    float diffuse = 0.25 * (sin(psi) + (3.14159265 - psi) * cosPsi);
    float shininess = max(uLightTerms.w, 1.0);
    float specular = cosPsi > -1.0 ? cos(0.5 * psi) * sqrt(3.14159265 / (2.0 * shininess)) : 0.0;
    return base * (uLightTerms.x + uLightTerms.y * diffuse) + vec3(uLightTerms.z * specular);
}

// Marches the LoD volume from t to tFar (or early ray termination), compositing into `accum`
// (premultiplied) under what the exact tubes left. A ray without a tube hit so far takes its
// depth (and the normal facing the eye) where its opacity passes 1/2.
void vrcLodMarch(Ray ray, float t, float tFar, inout vec4 accum, inout float firstDepth, inout vec3 firstNormal) {
    bool depthSet = !isinf(firstDepth);
#ifdef VRC_LOD_STATS
    atomicAdd(vrcLodSamples[kVrcLodMaxLevels], 1u);
#endif
    for (int steps = 0; steps < 65536 && t < tFar && accum.a < uOpacityThreshold; ++steps) {
        int level = min(max(vrcLodLevel(t, accum.a), uLodMinLevel), uLodLevels - 1);
        float size = uVoxelSize * exp2(float(level));
        float dt = min(size, tFar - t);
        vec3 g = (ray.origin + (t + 0.5 * dt) * ray.dir - uGridOrigin) / size;
        vec4 s = texture(vrcLodAtlas, (vec3(uLodAtlasX[level] + 1.0, 1.0, 1.0) + g) * uLodAtlasInvSize);
#ifdef VRC_LOD_STATS
        atomicAdd(vrcLodSamples[level], 1u);
#endif
        if (s.a > 0.0) {
            float alpha = 1.0 - exp(-s.a * dt);
            vec3 rgb = clamp(vrcLodShade(s.rgb / s.a, ray.dir), 0.0, 1.0);
            accum.rgb += (1.0 - accum.a) * alpha * rgb;
            accum.a += (1.0 - accum.a) * alpha;
            if (!depthSet && accum.a >= 0.5) {
                firstDepth = viewDepth(ray, t + 0.5 * dt);
                firstNormal = -ray.dir;
                depthSet = true;
            }
        }
        t += dt;
    }
}

#endif  // TC_VRC_LOD_GLSL
