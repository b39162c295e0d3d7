// Voxel-based line ray casting (Kanzler, Rautenhaus & Westermann 2019): one invocation per pixel
// walks the VRC grid (core/vrc_model.h) front to back with a 3D DDA, skips empty voxels through
// the header, intersects the voxel's line pieces as rounded cones (cylinder part + spheres at the
// piece ends, shaders/rounded_cone.glsl), accepts only hits inside the current voxel's ray
// interval, sorts them, blends each line once per voxel and composites front to back with early
// ray termination. gl/vrc_renderer.cpp sets everything below.
//
// Defines: QUANTIZED (compact 16-byte pieces, else exact 64-byte pieces), TRANSPARENT (else
// opaque: the first accepted hit), NEIGHBORS (also test the pieces of the 26 neighbouring voxels,
// for tubes that stick out of the voxel holding their axis), AMBIENT_OCCLUSION (cone traced AO of
// the density volume, as the rasterized path), SOFT_SHADOWS (a cone toward the light through the
// same density volume, growing footprint = mip level).
#include "camera.glsl"
#include "rounded_cone.glsl"
#include "shading.glsl"
#include "frame_uniforms.glsl"
// Included unconditionally and before ambient_occlusion.glsl: the shader library expands each
// file once, at its first #include, whatever #ifdef surrounds it, and ambient_occlusion.glsl's
// include sits inside #ifdef AMBIENT_OCCLUSION. Unused, its uniforms are optimised away.
#include "cone_tracing.glsl"
#include "ambient_occlusion.glsl"
#ifdef SOFT_SHADOWS
uniform float uShadowTanHalfAperture;
uniform float uShadowDistance;  // world units
uniform float uShadowStrength;
uniform float uShadowStartOffset;
#endif

layout(local_size_x = 8, local_size_y = 8) in;

// Header: (offset, count | neighbourhood bit) per voxel, x fastest.
layout(std430, binding = 0) readonly buffer VrcHeader { uvec2 vrcVoxels[]; };
#ifdef QUANTIZED
// ends (2 x 16-bit codes), polyline id, RGBA8 colour, 2 x unorm16 radius (of uMaxRadius).
layout(std430, binding = 1) readonly buffer VrcPieces { uvec4 vrcPieces[]; };
#else
struct VrcExactPiece {
    vec4 a;      // xyz, radius
    vec4 b;
    vec4 color;  // linear RGBA, straight alpha
    uvec4 info;  // polyline id, end flags (bit 0: a is a polyline vertex, bit 1: b)
};
layout(std430, binding = 1) readonly buffer VrcPieces { VrcExactPiece vrcPieces[]; };
#endif

uniform ivec3 uGridSize;
uniform vec3 uGridOrigin;
uniform float uVoxelSize;
uniform int uQuantization;
uniform float uMaxRadius;
uniform float uOpacityThreshold;
uniform vec3 uLightDir;    // world space, toward the light
uniform vec4 uLightTerms;  // ambient, diffuse, specular, shininess

layout(rgba32f, binding = 0) uniform writeonly image2D uColor;       // premultiplied linear RGBA
layout(rgba32f, binding = 1) uniform writeonly image2D uNormalDepth; // world normal, view depth
layout(r32ui, binding = 2) uniform writeonly uimage2D uId;           // polyline id
layout(r32f, binding = 3) uniform writeonly image2D uAo;             // AO factor of the first hit

const uint kVrcInteriorFace = 6u;
const uint kVrcNeighbourhoodBit = 0x80000000u;
const uint kVrcCountMask = 0x7FFFFFFFu;
const uint kNoLine = 0xFFFFFFFFu;

struct VrcPiece {
    RoundedCone cone;
    vec4 color;
    uint line;
    bool vertexA, vertexB;
};

// Twin of tc::decodeEnd (core/vrc_model.cpp).
vec3 vrcDecodeEnd(ivec3 v, uint code) {
    uint face = code >> 13u, bin = code & 0x1FFFu;
    vec3 p = vec3(v);
    if (face == kVrcInteriorFace) {
        uint m = uint(min(uQuantization, 16));
        uvec3 cell = uvec3(bin % m, bin / m % m, bin / m / m);
        p += (vec3(cell) + 0.5) / float(m);
    } else {
        int axis = int(face / 2u);
        ivec2 plane = axis == 0 ? ivec2(1, 2) : (axis == 1 ? ivec2(0, 2) : ivec2(0, 1));
        uint q = uint(uQuantization);
        p[axis] += float(face & 1u);
        p[plane.x] += (float(bin % q) + 0.5) / float(q);
        p[plane.y] += (float(bin / q) + 0.5) / float(q);
    }
    return uGridOrigin + p * uVoxelSize;
}

VrcPiece vrcPiece(uint i, ivec3 v) {
    VrcPiece p;
#ifdef QUANTIZED
    uvec4 c = vrcPieces[i];
    uint codeA = c.x & 0xFFFFu, codeB = c.x >> 16u;
    p.cone = RoundedCone(vrcDecodeEnd(v, codeA), uMaxRadius * float(c.w & 0xFFFFu) / 65535.0,
                         vrcDecodeEnd(v, codeB), uMaxRadius * float(c.w >> 16u) / 65535.0);
    p.color = unpackUnorm4x8(c.z);
    p.line = c.y;
    p.vertexA = (codeA >> 13u) == kVrcInteriorFace;
    p.vertexB = (codeB >> 13u) == kVrcInteriorFace;
#else
    VrcExactPiece e = vrcPieces[i];
    p.cone = RoundedCone(e.a.xyz, e.a.w, e.b.xyz, e.b.w);
    p.color = e.color;
    p.line = e.info.x;
    p.vertexA = (e.info.y & 1u) != 0u;
    p.vertexB = (e.info.y & 2u) != 0u;
#endif
    return p;
}

#ifdef TRANSPARENT
const int kMaxHits = 16;
#else
const int kMaxHits = 1;
#endif
// The accepted hits of the current voxel, sorted by t (insertion sort; the farthest drops out).
float hitT[kMaxHits];
vec3 hitNormal[kMaxHits];
uint hitPiece[kMaxHits];
uint hitLine[kMaxHits];
ivec3 hitVoxel[kMaxHits];
int hitCount = 0;

void insertHit(float t, vec3 n, uint piece, uint line, ivec3 v) {
    int i = min(hitCount, kMaxHits - 1);
    if (hitCount == kMaxHits && t >= hitT[i]) return;
    while (i > 0 && hitT[i - 1] > t) {
        hitT[i] = hitT[i - 1];
        hitNormal[i] = hitNormal[i - 1];
        hitPiece[i] = hitPiece[i - 1];
        hitLine[i] = hitLine[i - 1];
        hitVoxel[i] = hitVoxel[i - 1];
        --i;
    }
    hitT[i] = t;
    hitNormal[i] = n;
    hitPiece[i] = piece;
    hitLine[i] = line;
    hitVoxel[i] = v;
    hitCount = min(hitCount + 1, kMaxHits);
}

// Tests the pieces of voxel v against the ray; keeps hits in [tEnter, tExit) (the current voxel).
void testVoxel(Ray ray, ivec3 v, float tEnter, float tExit) {
    if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, uGridSize))) return;
    uvec2 h = vrcVoxels[(v.z * uGridSize.y + v.y) * uGridSize.x + v.x];
    uint count = h.y & kVrcCountMask;
    for (uint k = 0u; k < count; ++k) {
        uint i = h.x + k;
        VrcPiece p = vrcPiece(i, v);
        // Bounding sphere of the rounded cone first: most pieces of a voxel miss the ray, and this
        // costs a fraction of the full intersector.
        vec3 centre = 0.5 * (p.cone.x0 + p.cone.x1) - ray.origin;
        float bound = 0.5 * length(p.cone.x1 - p.cone.x0) + max(p.cone.r0, p.cone.r1);
        vec3 perp = centre - dot(centre, ray.dir) * ray.dir;
        if (dot(perp, perp) > bound * bound) continue;
        ConeInterval iv = intersectRoundedCone(ray, p.cone);
        if (!iv.hit) continue;
        // The visible surface rule of the opaque path (shaders/visible_hit.glsl): the entry, or
        // the exit when the ray starts inside the tube.
        float t = iv.tIn > 0.0 ? iv.tIn : iv.tOut;
        vec3 n = iv.tIn > 0.0 ? iv.nIn : iv.nOut;
        if (!(t > 0.0) || t < tEnter || t >= tExit) continue;
#ifdef TRANSPARENT
        // Blend the union of a line's pieces once: a hit on the spherical cap past an end shared
        // with the next piece (a face end) lies inside that piece's tube, so it is not a surface
        // of the union. The cap starts at the circle where the sphere touches the tangent cone,
        // r * sin(alpha) = r (r0 - r1) / L along the axis from the sphere's centre, so collinear
        // pieces of a straight (also tapered) tube split its surface exactly; at bends the outer
        // wedge between two caps is left open (opaque rendering keeps the caps and fills it).
        vec3 axis = p.cone.x1 - p.cone.x0;
        float len = length(axis);
        if (len > abs(p.cone.r0 - p.cone.r1)) {
            float sinAlpha = (p.cone.r0 - p.cone.r1) / len;
            float y = dot(ray.origin + t * ray.dir - p.cone.x0, axis) / len;
            if ((y < p.cone.r0 * sinAlpha && !p.vertexA) || (y > len + p.cone.r1 * sinAlpha && !p.vertexB)) continue;
        }
#endif
        insertHit(t, n, i, p.line, v);
    }
}

// cone: the hit piece (its own tube is excluded from the AO and shadow cones).
vec3 shadeHit(Ray ray, float t, vec3 n, vec4 base, RoundedCone cone, out float ao) {
    vec3 pos = ray.origin + t * ray.dir;
    vec3 facing = dot(n, ray.dir) <= 0.0 ? n : -n;
    ConeOwnTube own = coneOwnTube(vec4(cone.x0, cone.r0), vec4(cone.x1, cone.r1), base.a, base.a);
    ao = 1.0;
#ifdef AMBIENT_OCCLUSION
    ao = tubeAmbientOcclusion(pos, facing, own);
#endif
    float visibility = 1.0;
#ifdef SOFT_SHADOWS
    visibility = 1.0 - traceOcclusionCone(pos, uLightDir, uShadowTanHalfAperture, uShadowDistance, uShadowStrength,
                                          uShadowStartOffset, own);
#endif
    return shadeBlinnPhong(base.rgb * ao, n, ray.dir, uLightDir, uLightTerms.x, uLightTerms.y * visibility,
                           uLightTerms.z * visibility, uLightTerms.w);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(uTargetSize.x) || pixel.y >= int(uTargetSize.y)) return;
    Ray ray = pixelRay(frameCamera(), vec2(pixel) + 0.5);

    vec4 accum = vec4(0.0);
    float firstDepth = uintBitsToFloat(0x7F800000u);
    vec3 firstNormal = vec3(0.0);
    uint firstLine = kNoLine;
    float firstAo = 1.0;

    // Ray / grid box (slabs).
    vec3 lo = uGridOrigin, hi = uGridOrigin + vec3(uGridSize) * uVoxelSize;
    vec3 invDir = vec3(ray.dir.x != 0.0 ? 1.0 / ray.dir.x : 1e30, ray.dir.y != 0.0 ? 1.0 / ray.dir.y : 1e30,
                       ray.dir.z != 0.0 ? 1.0 / ray.dir.z : 1e30);
    vec3 ta = (lo - ray.origin) * invDir, tb = (hi - ray.origin) * invDir;
    vec3 tNear3 = min(ta, tb), tFar3 = max(ta, tb);
    float tNear = max(max(tNear3.x, tNear3.y), max(tNear3.z, 0.0));
    float tFar = min(min(tFar3.x, tFar3.y), tFar3.z);

    if (tNear < tFar) {
        // Amanatides & Woo DDA in world t.
        vec3 g = (ray.origin + tNear * ray.dir - uGridOrigin) / uVoxelSize;
        ivec3 v = clamp(ivec3(floor(g)), ivec3(0), uGridSize - 1);
        ivec3 stepDir = ivec3(sign(ray.dir));
        vec3 tDelta = abs(uVoxelSize * invDir);
        vec3 tMax;
        for (int k = 0; k < 3; ++k) {
            if (stepDir[k] == 0) { tMax[k] = 1e30; continue; }
            float face = uGridOrigin[k] + float(v[k] + (stepDir[k] > 0 ? 1 : 0)) * uVoxelSize;
            tMax[k] = (face - ray.origin[k]) * invDir[k];
        }
        float tEnter = tNear;
        bool done = false;
        while (!done) {
            float tExit = min(min(tMax.x, tMax.y), tMax.z);
            uint header = vrcVoxels[(v.z * uGridSize.y + v.y) * uGridSize.x + v.x].y;
#ifdef NEIGHBORS
            bool occupied = (header & kVrcNeighbourhoodBit) != 0u;
#else
            bool occupied = (header & kVrcCountMask) != 0u;
#endif
            if (occupied) {
                hitCount = 0;
#ifdef NEIGHBORS
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) testVoxel(ray, v + ivec3(dx, dy, dz), tEnter, tExit);
#else
                testVoxel(ray, v, tEnter, tExit);
#endif
                for (int i = 0; i < hitCount; ++i) {
#ifdef TRANSPARENT
                    // Each line once per voxel: the nearest of its hits here.
                    bool seen = false;
                    for (int j = 0; j < i; ++j) seen = seen || hitLine[j] == hitLine[i];
                    if (seen) continue;
#endif
                    VrcPiece p = vrcPiece(hitPiece[i], hitVoxel[i]);
                    float ao;
                    vec3 rgb = shadeHit(ray, hitT[i], hitNormal[i], p.color, p.cone, ao);
                    if (firstLine == kNoLine) {
                        firstDepth = viewDepth(ray, hitT[i]);
                        firstNormal = hitNormal[i];
                        firstLine = hitLine[i];
                        firstAo = ao;
                    }
#ifdef TRANSPARENT
                    // As every transparent path: shaded colour clamped to [0, 1], blended "under".
                    float a = p.color.a;
                    accum.rgb += (1.0 - accum.a) * a * clamp(rgb, 0.0, 1.0);
                    accum.a += (1.0 - accum.a) * a;
#else
                    accum = vec4(rgb, 1.0);
#endif
                }
#ifdef TRANSPARENT
                done = accum.a >= uOpacityThreshold;
#else
                done = hitCount > 0;
#endif
            }
            // Next voxel.
            if (tMax.x <= tMax.y && tMax.x <= tMax.z) {
                v.x += stepDir.x;
                tMax.x += tDelta.x;
            } else if (tMax.y <= tMax.z) {
                v.y += stepDir.y;
                tMax.y += tDelta.y;
            } else {
                v.z += stepDir.z;
                tMax.z += tDelta.z;
            }
            tEnter = tExit;
            if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, uGridSize)) || tEnter > tFar) done = true;
        }
    }
    imageStore(uColor, pixel, accum);
    imageStore(uNormalDepth, pixel, vec4(firstNormal, firstDepth));
    imageStore(uId, pixel, uvec4(firstLine));
    imageStore(uAo, pixel, vec4(firstAo));
}
