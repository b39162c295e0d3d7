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
// same density volume, growing footprint = mip level), HARD_SHADOWS (a ray toward the light against
// the representative lines of one LoD level), VRC_Q (the quantization, with QUANTIZED), BRICK_SKIP
// (empty space skipping over bricks of 4^3 voxels), VRC_PIECE_BLOCKS and VRC_BLOCK_SHIFT (the
// piece array's storage blocks, below), VRC_PIECE_TEXTURE (quantized pieces read through one texture
// buffer over the whole array instead), VRC_PATH_LENGTH_OPACITY (with TRANSPARENT: a hit's alpha
// depends on the ray's chord through the hit piece, below), VRC_DENSITY_AO, VRC_PRECOMPUTED_AO,
// VRC_DENSITY_SHADOWS, VRC_HARD_TUBE_SHADOWS (the paper's lighting, shaders/vrc_lighting.glsl), VRC_LOD (rays leave the tubes for the
// LoD volume in the distance and, transparent, at high accumulated opacity: shaders/vrc_lod.glsl),
// VRC_LOD_STATS (with VRC_LOD: count the samples per level), VRC_PAPER (render.vrc.encoding "paper":
// the packed pieces and 5-byte headers of core/vrc_packed.h instead of QUANTIZED's, with
// VRC_PAPER_BYTES, VRC_PAPER_BIN_BITS, VRC_PAPER_M, VRC_PAPER_LINE_BITS, VRC_PAPER_WIDE_COUNTS,
// VRC_PAPER_COPIES, VRC_PAPER_RADII and VRC_Q;
// never with NEIGHBORS), VRC_GLOBAL_IDS (with VRC_PAPER: the polyline id image reads the
// pieces' global ids from a side array; else the local line ids serve, which only tell lines
// apart within a voxel), HALO (with TRANSPARENT: style.halo's ring, HALO_WIDTH, HALO_DEPTH and
// HALO_COLOR; vrcHaloHit below).
//
// Copies (core/vrc_model.h): without NEIGHBORS the model holds a copy of each piece in every
// neighbour its tube reaches, so the current voxel's pieces are all the tubes with surface in it.
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

layout(local_size_x = VRC_GROUP_SIZE, local_size_y = VRC_GROUP_SIZE) in;  // gl/vrc_renderer.cpp

#ifdef VRC_PAPER
// Header (Kanzler et al. 2019, Sec. 6.2: 5 bytes per voxel): the first piece per voxel, and the
// piece count in one byte, four voxels per word (x fastest).
layout(std430, binding = SSBO_VRC_HEADER) readonly buffer VrcPaperOffsets { uint vrcPaperOffsets[]; };
layout(std430, binding = SSBO_VRC_PAPER_COUNTS) readonly buffer VrcPaperCounts { uint vrcPaperCounts[]; };
// The packed pieces as 32-bit words (GL_R32UI); piece i is the bit string at byte i x VRC_PAPER_BYTES.
layout(binding = TEXTURE_VRC_PIECE_TEXELS) uniform usamplerBuffer vrcPaperWords;
#ifdef VRC_GLOBAL_IDS
layout(binding = TEXTURE_VRC_GLOBAL_IDS) uniform usamplerBuffer vrcGlobalIds;
#endif
uniform uint uVrcPalette[256];  // RGBA8
uniform uint uVrcRadiusCode;    // without VRC_PAPER_RADII: every end's unorm16 radius (of uMaxRadius)
// (offset, count) of voxel vi, as the 16-byte model's header (no neighbourhood bit: never NEIGHBORS).
uint vrcHeaderCount(int vi) {
#ifdef VRC_PAPER_WIDE_COUNTS
    return (vrcPaperCounts[vi >> 1] >> (16u * uint(vi & 1))) & 0xFFFFu;  // 2-byte counts
#else
    return (vrcPaperCounts[vi >> 2] >> (8u * uint(vi & 3))) & 0xFFu;
#endif
}
uvec2 vrcHeaderAt(int vi) {
    return uvec2(vrcPaperOffsets[vi], vrcHeaderCount(vi));
}
#else
// Header: (offset, count | neighbourhood bit) per voxel, x fastest.
layout(std430, binding = SSBO_VRC_HEADER) readonly buffer VrcHeader { uvec2 vrcVoxels[]; };
uvec2 vrcHeaderAt(int vi) {
    return vrcVoxels[vi];
}
uint vrcHeaderCount(int vi) {
    return vrcVoxels[vi].y;
}
#endif
#ifdef VRC_PAPER
// The pieces are words of vrcPaperWords (above), decoded by vrcPiece.
#elif defined(QUANTIZED)
// ends (2 x 16-bit codes), polyline id, RGBA8 colour, 2 x unorm16 radius (of uMaxRadius).
#define VRC_PIECE_T uvec4
#else
struct VrcExactPiece {
    vec4 a;      // xyz, radius
    vec4 b;
    vec4 color;  // linear RGBA, straight alpha
    uvec4 info;  // polyline id, end flags (bit 0: a is a polyline vertex, bit 1: b)
};
#define VRC_PIECE_T VrcExactPiece
#endif
#ifndef VRC_PAPER
#ifndef VRC_PIECE_TEXTURE
// The piece array in VRC_PIECE_BLOCKS blocks of 2^VRC_BLOCK_SHIFT pieces (one shader storage
// block is capped at GL_MAX_SHADER_STORAGE_BLOCK_SIZE, 128 MiB on llvmpipe): block 0 at
// SSBO_VRC_PIECES, blocks 1.. at SSBO_VRC_PIECE_BLOCKS + 0, 1, ... (gl/vrc_renderer.cpp). Piece i is in block i >> VRC_BLOCK_SHIFT.
layout(std430, binding = SSBO_VRC_PIECES) readonly buffer VrcPieces0 { VRC_PIECE_T vrcPieces0[]; };
#if VRC_PIECE_BLOCKS > 1
layout(std430, binding = SSBO_VRC_PIECE_BLOCKS) readonly buffer VrcPieces1 { VRC_PIECE_T vrcPieces1[]; };
#endif
#if VRC_PIECE_BLOCKS > 2
layout(std430, binding = SSBO_VRC_PIECE_BLOCKS + 1) readonly buffer VrcPieces2 { VRC_PIECE_T vrcPieces2[]; };
#endif
#if VRC_PIECE_BLOCKS > 3
layout(std430, binding = SSBO_VRC_PIECE_BLOCKS + 2) readonly buffer VrcPieces3 { VRC_PIECE_T vrcPieces3[]; };
#endif
#if VRC_PIECE_BLOCKS > 4
layout(std430, binding = SSBO_VRC_PIECE_BLOCKS + 3) readonly buffer VrcPieces4 { VRC_PIECE_T vrcPieces4[]; };
#endif
#if VRC_PIECE_BLOCKS > 5
layout(std430, binding = SSBO_VRC_PIECE_BLOCKS + 4) readonly buffer VrcPieces5 { VRC_PIECE_T vrcPieces5[]; };
#endif
#if VRC_PIECE_BLOCKS > 6
layout(std430, binding = SSBO_VRC_PIECE_BLOCKS + 5) readonly buffer VrcPieces6 { VRC_PIECE_T vrcPieces6[]; };
#endif
#if VRC_PIECE_BLOCKS > 7
layout(std430, binding = SSBO_VRC_PIECE_BLOCKS + 6) readonly buffer VrcPieces7 { VRC_PIECE_T vrcPieces7[]; };
#endif
#if VRC_PIECE_BLOCKS > 8
#error "at most 8 piece blocks (VrcRenderer::kMaxPieceBlocks)"
#endif
#endif  // !VRC_PIECE_TEXTURE

#ifdef VRC_PIECE_TEXTURE
// The whole piece array as one texture buffer (GL_RGBA32UI, gl/vrc_renderer.cpp): llvmpipe
// gathers a texel fetch with vector code, while a storage buffer read at per-lane addresses is a
// loop over the lanes with a branch per lane and component, and the blocks need one read per
// block (both sides of an if run on llvmpipe). With the candidate masks of testVoxel the piece
// reads are a large part of the ray cast (docs/performance.md, "Design notes"; without the masks,
// texture buffers made no measurable difference).
layout(binding = TEXTURE_VRC_PIECE_TEXELS) uniform usamplerBuffer vrcPieceTex;
#endif

VRC_PIECE_T vrcFetchPiece(uint i) {
#ifdef VRC_PIECE_TEXTURE
    return texelFetch(vrcPieceTex, int(i));
#elif VRC_PIECE_BLOCKS == 1
    return vrcPieces0[i];
#else
    // Blocks are slabs of voxels in z order, so the lanes of a workgroup nearly always agree.
    uint block = i >> uint(VRC_BLOCK_SHIFT), j = i & ((1u << uint(VRC_BLOCK_SHIFT)) - 1u);
    if (block == 0u) return vrcPieces0[j];
#if VRC_PIECE_BLOCKS > 2
    if (block == 1u) return vrcPieces1[j];
#endif
#if VRC_PIECE_BLOCKS > 3
    if (block == 2u) return vrcPieces2[j];
#endif
#if VRC_PIECE_BLOCKS > 4
    if (block == 3u) return vrcPieces3[j];
#endif
#if VRC_PIECE_BLOCKS > 5
    if (block == 4u) return vrcPieces4[j];
#endif
#if VRC_PIECE_BLOCKS > 6
    if (block == 5u) return vrcPieces5[j];
#endif
#if VRC_PIECE_BLOCKS > 7
    if (block == 6u) return vrcPieces6[j];
#endif
    // The last block.
#if VRC_PIECE_BLOCKS == 2
    return vrcPieces1[j];
#elif VRC_PIECE_BLOCKS == 3
    return vrcPieces2[j];
#elif VRC_PIECE_BLOCKS == 4
    return vrcPieces3[j];
#elif VRC_PIECE_BLOCKS == 5
    return vrcPieces4[j];
#elif VRC_PIECE_BLOCKS == 6
    return vrcPieces5[j];
#elif VRC_PIECE_BLOCKS == 7
    return vrcPieces6[j];
#else
    return vrcPieces7[j];
#endif
#endif
}
#endif  // !VRC_PAPER

#ifdef BRICK_SKIP
// Per brick of kBrick^3 voxels: 0 when no voxel in it can hold a surface (gl/vrc_renderer.cpp).
const int kBrick = VRC_BRICK;
layout(std430, binding = SSBO_VRC_BRICKS) readonly buffer VrcBricks { uint vrcBricks[]; };
uniform ivec3 uBrickGridSize;
#endif
uniform ivec3 uGridSize;
uniform vec3 uGridOrigin;
uniform float uVoxelSize;
uniform float uMaxRadius;
uniform float uOpacityThreshold;

#ifdef VRC_LOD
#include "vrc_lod.glsl"
#endif

layout(rgba32f, binding = IMAGE_VRC_COLOR) uniform writeonly image2D uColor;       // premultiplied linear RGBA
layout(rgba32f, binding = IMAGE_VRC_NORMAL_DEPTH) uniform writeonly image2D uNormalDepth; // world normal, view depth
layout(r32ui, binding = IMAGE_VRC_ID) uniform writeonly uimage2D uId;           // polyline id
layout(r32f, binding = IMAGE_VRC_AO) uniform writeonly image2D uAo;             // AO factor of the first hit

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

#if defined(QUANTIZED) || defined(VRC_PAPER)
// Twin of tc::decodeEnd (core/vrc_model.cpp). The quantization is a compile-time constant
// (VRC_Q, set by gl/vrc_renderer.cpp): llvmpipe has no vector integer division, so a division by
// a uniform runs as one scalar division per lane; by a constant it becomes shifts or a multiply.
const uint kVrcQ = uint(VRC_Q);
#ifdef VRC_PAPER
const uint kVrcM = uint(VRC_PAPER_M);  // the packed encoding's interior lattice (core/vrc_packed.h)
#else
const uint kVrcM = min(kVrcQ, 16u);  // interior lattice (kInteriorLattice)
#endif
vec3 vrcDecodeEnd(ivec3 v, uint face, uint bin) {
    vec3 p = vec3(v);
    if (face == kVrcInteriorFace) {
        uvec3 cell = uvec3(bin % kVrcM, bin / kVrcM % kVrcM, bin / (kVrcM * kVrcM));
        p += (vec3(cell) + 0.5) / float(kVrcM);
    } else {
        int axis = int(face / 2u);
        ivec2 plane = axis == 0 ? ivec2(1, 2) : (axis == 1 ? ivec2(0, 2) : ivec2(0, 1));
        p[axis] += float(face & 1u);
        p[plane.x] += (float(bin % kVrcQ) + 0.5) / float(kVrcQ);
        p[plane.y] += (float(bin / kVrcQ) + 0.5) / float(kVrcQ);
    }
    return uGridOrigin + p * uVoxelSize;
}
#endif

#ifdef VRC_PAPER
// Twin of tc::unpackVrcPiece (core/vrc_packed.cpp). Field widths and shifts are constants.
const uint kPaperBytes = uint(VRC_PAPER_BYTES);
const uint kPaperBinBits = uint(VRC_PAPER_BIN_BITS);
const uint kPaperEndBits = kPaperBinBits + 3u;
const uint kPaperColorShift = 2u * kPaperEndBits;
const uint kPaperLineShift = kPaperColorShift + 8u;
const uint kPaperLineBits = uint(VRC_PAPER_LINE_BITS);
const uint kPaperOffsetShift = kPaperLineShift + kPaperLineBits;
#ifdef VRC_PAPER_COPIES
const uint kPaperRadiusShift = kPaperOffsetShift + 6u;
#else
const uint kPaperRadiusShift = kPaperOffsetShift;
#endif
// Bits [shift, shift + n) of the 96-bit value a (a.x lowest), n < 32, shift + n <= 96.
uint vrcPaperField(uvec3 a, uint shift, uint n) {
    uint lo = shift < 32u ? a.x : (shift < 64u ? a.y : a.z);
    uint hi = shift < 32u ? a.y : a.z;
    uint r = shift & 31u;
    uint v = r == 0u ? lo : ((lo >> r) | (hi << (32u - r)));
    return v & ((1u << n) - 1u);
}
vec3 vrcPaperEnd(ivec3 home, uint code) {
    uint face = code >> kPaperBinBits, bin = code & ((1u << kPaperBinBits) - 1u);
    // Face ids 6 and 7: a vertex end, the id's low bit above the bin bits of its lattice index.
    if (face >= kVrcInteriorFace) return vrcDecodeEnd(home, kVrcInteriorFace, ((face - kVrcInteriorFace) << kPaperBinBits) | bin);
    return vrcDecodeEnd(home, face, bin);
}
#endif

// Home voxel offset of a copy (core/vrc_model.h, Copies): 2-bit two's complement per axis.
ivec3 vrcHomeOffset(uint bits) {
    return ivec3(bitfieldExtract(int(bits), 0, 2), bitfieldExtract(int(bits), 2, 2), bitfieldExtract(int(bits), 4, 2));
}

VrcPiece vrcPiece(uint i, ivec3 v) {
    VrcPiece p;
#ifdef VRC_PAPER
    // The piece's bytes start in word byte / 4 at bit 8 (byte & 3): align three words (at most
    // 3 + 9 bytes are read; the array is padded by two words).
    uint byte = i * kPaperBytes;
    int w = int(byte >> 2u);
    uint s = 8u * (byte & 3u);
    uint w0 = texelFetch(vrcPaperWords, w).x, w1 = texelFetch(vrcPaperWords, w + 1).x;
#if VRC_PAPER_BYTES > 5
    uint w2 = texelFetch(vrcPaperWords, w + 2).x;
#else
    uint w2 = 0u;  // s + 40 bits <= 64: two words hold the piece
#endif
    uvec3 a = s == 0u ? uvec3(w0, w1, w2) : uvec3((w0 >> s) | (w1 << (32u - s)), (w1 >> s) | (w2 << (32u - s)), w2 >> s);
    uint codeA = vrcPaperField(a, 0u, kPaperEndBits), codeB = vrcPaperField(a, kPaperEndBits, kPaperEndBits);
#ifdef VRC_PAPER_COPIES
    ivec3 home = v + vrcHomeOffset(vrcPaperField(a, kPaperOffsetShift, 6u));
#else
    ivec3 home = v;
#endif
#ifdef VRC_PAPER_RADII
    uint radii = vrcPaperField(a, kPaperRadiusShift, 16u);
    float r0 = uMaxRadius * float(radii & 0xFFu) / 255.0, r1 = uMaxRadius * float(radii >> 8u) / 255.0;
#else
    // The 16-byte model's expression: the same radius bit for bit.
    float r0 = uMaxRadius * float(uVrcRadiusCode) / 65535.0, r1 = r0;
#endif
    p.cone = RoundedCone(vrcPaperEnd(home, codeA), r0, vrcPaperEnd(home, codeB), r1);
    p.color = unpackUnorm4x8(uVrcPalette[vrcPaperField(a, kPaperColorShift, 8u)]);
#ifdef VRC_GLOBAL_IDS
    p.line = texelFetch(vrcGlobalIds, int(i)).x;
#else
    p.line = vrcPaperField(a, kPaperLineShift, kPaperLineBits);
#endif
    p.vertexA = (codeA >> kPaperBinBits) >= kVrcInteriorFace;
    p.vertexB = (codeB >> kPaperBinBits) >= kVrcInteriorFace;
#elif defined(QUANTIZED)
    uvec4 c = vrcFetchPiece(i);
    uint codeA = c.x & 0xFFFFu, codeB = c.x >> 16u;
    ivec3 home = v + vrcHomeOffset(c.y >> 26u);
    p.cone = RoundedCone(vrcDecodeEnd(home, codeA >> 13u, codeA & 0x1FFFu), uMaxRadius * float(c.w & 0xFFFFu) / 65535.0,
                         vrcDecodeEnd(home, codeB >> 13u, codeB & 0x1FFFu), uMaxRadius * float(c.w >> 16u) / 65535.0);
    p.color = unpackUnorm4x8(c.z);
    p.line = c.y & 0x03FFFFFFu;
    p.vertexA = (codeA >> 13u) == kVrcInteriorFace;
    p.vertexB = (codeB >> 13u) == kVrcInteriorFace;
#else
    VrcExactPiece e = vrcFetchPiece(i);
    p.cone = RoundedCone(e.a.xyz, e.a.w, e.b.xyz, e.b.w);
    p.color = e.color;
    p.line = e.info.x;
    p.vertexA = (e.info.y & 1u) != 0u;
    p.vertexB = (e.info.y & 2u) != 0u;
#endif
    return p;
}

// Squared distance between the ray's part in [tEnter, tExit] and the segment [x0, x1] (closest
// points of two segments, Ericson, Real-Time Collision Detection 5.1.9; dir is unit length).
float raySegmentDistance2(Ray ray, float tEnter, float tExit, vec3 x0, vec3 x1) {
    vec3 e = x1 - x0;
    vec3 w = ray.origin + tEnter * ray.dir - x0;
    float len = tExit - tEnter;
    float b = dot(ray.dir, e), c = dot(e, e), d = dot(ray.dir, w), f = dot(e, w);
    float denom = c - b * b;
    float t = denom > 1e-12 * c ? clamp((b * f - c * d) / denom, 0.0, len) : 0.0;
    float s = c > 0.0 ? clamp((f + t * b) / c, 0.0, 1.0) : 0.0;
    t = clamp(s * b - d, 0.0, len);
    vec3 r = w + t * ray.dir - s * e;
    return dot(r, r);
}

#ifdef HARD_SHADOWS
// Representative lines of one LoD level (core/vrc_representative.h), per level voxel x fastest:
// a.xyz + radius, b.xyz + weight (0 = empty voxel).
layout(std430, binding = SSBO_VRC_SHADOW_LINES) readonly buffer VrcShadowLines { vec4 vrcShadowLines[]; };
uniform ivec3 uShadowGridSize;
uniform float uShadowVoxelSize;

// 0 when the ray from `pos` toward the light meets a representative line's tube (capsule of its
// radius) farther than one level voxel away, else 1. The first voxel length is skipped: the
// shaded tube's own representative lies within it (and would shadow every point of the tube).
float hardShadowVisibility(vec3 pos) {
    Ray ray;
    ray.origin = pos;
    ray.dir = normalize(uLightDir);
    float tStart = uShadowVoxelSize;
    vec3 lo = uGridOrigin, hi = uGridOrigin + vec3(uShadowGridSize) * uShadowVoxelSize;
    vec3 invDir = vec3(ray.dir.x != 0.0 ? 1.0 / ray.dir.x : 1e30, ray.dir.y != 0.0 ? 1.0 / ray.dir.y : 1e30,
                       ray.dir.z != 0.0 ? 1.0 / ray.dir.z : 1e30);
    vec3 ta = (lo - ray.origin) * invDir, tb = (hi - ray.origin) * invDir;
    vec3 tNear3 = min(ta, tb), tFar3 = max(ta, tb);
    float tNear = max(max(tNear3.x, tNear3.y), max(tNear3.z, 0.0));
    float tFar = min(min(tFar3.x, tFar3.y), tFar3.z);
    if (!(tNear < tFar)) return 1.0;
    vec3 g = (ray.origin + tNear * ray.dir - uGridOrigin) / uShadowVoxelSize;
    ivec3 v = clamp(ivec3(floor(g)), ivec3(0), uShadowGridSize - 1);
    ivec3 stepDir = ivec3(sign(ray.dir));
    vec3 tDelta = abs(uShadowVoxelSize * invDir);
    vec3 tMax;
    for (int k = 0; k < 3; ++k) {
        float face = uGridOrigin[k] + float(v[k] + (stepDir[k] > 0 ? 1 : 0)) * uShadowVoxelSize;
        tMax[k] = stepDir[k] == 0 ? 1e30 : (face - ray.origin[k]) * invDir[k];
    }
    float visibility = 1.0;
    for (int steps = 0; steps < 4096; ++steps) {
        uint i = uint((v.z * uShadowGridSize.y + v.y) * uShadowGridSize.x + v.x);
        vec4 a = vrcShadowLines[2u * i], b = vrcShadowLines[2u * i + 1u];
        // The whole ray beyond tStart: a line's tube may reach out of its voxel.
        if (b.w > 0.0 && raySegmentDistance2(ray, tStart, tFar, a.xyz, b.xyz) <= a.w * a.w) {
            visibility = 0.0;
            break;
        }
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
        if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, uShadowGridSize))) break;
    }
    return visibility;
}
#endif

// The accepted hits of the current voxel, sorted by t, in VRC_SLOTS named slots (hT0, hN0, ...).
// Hits are tested in increasing piece index (the piece array is in voxel index order, and
// NEIGHBORS visits the 27 voxels in that order too), so equal t keep index order: the order of a
// hit is its key (t, piece index). Named variables, not arrays: llvmpipe keeps a local array in memory and pays
// every access per lane, also with constant indices; an insertion sort and compositing loop over
// arrays was about half of the semi-transparent frame (docs/performance.md, "Design notes"). The
// colour is kept with the hit: re-reading and decoding the piece after sorting costs another
// per-lane SSBO gather. A voxel whose ray interval holds more hits than slots is composited in
// batches (main): each batch re-tests the voxel and keeps the VRC_SLOTS nearest hits past the last
// one blended, so every hit is blended, in order, however many tubes cross the voxel (Kanzler et
// al. 2019, Sec. 4: the intersections of a voxel are sorted in place, all of them).
#ifdef TRANSPARENT
#define VRC_SLOTS 8
#else
#define VRC_SLOTS 1
#endif
#if defined(TRANSPARENT) && defined(VRC_PATH_LENGTH_OPACITY)
// The hit's path-length alpha in hA (hC keeps the style alpha, which the AO and shadow cones'
// own-tube term uses: the density volume is built with it).
#define VRC_SLOT_A(k) float hA##k;
#define VRC_CX_A(k) float a_ = hA##k; hA##k = cA; cA = a_;
#define VRC_SHIFT_A(k, k1) hA##k = hA##k1;
#else
#define VRC_SLOT_A(k)
#define VRC_CX_A(k)
#define VRC_SHIFT_A(k, k1)
#endif
#if defined(AMBIENT_OCCLUSION) || defined(SOFT_SHADOWS) || defined(VRC_DENSITY_AO) || defined(VRC_DENSITY_SHADOWS)
// The hit piece's axis ends and radii (x0, r0), (x1, r1) in hE, hF: its own tube is excluded from
// the AO and shadow cones (shaders/cone_tracing.glsl, coneOwnTube).
#define VRC_HIT_CONE
#define VRC_SLOT(k) float hT##k; vec3 hN##k; vec4 hC##k; uint hL##k; vec4 hE##k; vec4 hF##k; VRC_SLOT_A(k)
// Compare-exchange of slot k with the carried hit (cT, ...): the slot keeps the nearer one (ties
// keep the earlier hit first, as a stable insertion sort).
#define VRC_CX(k) if (cT < hT##k) { float t_ = hT##k; hT##k = cT; cT = t_; vec3 n_ = hN##k; hN##k = cN; cN = n_; vec4 c_ = hC##k; hC##k = cC; cC = c_; uint l_ = hL##k; hL##k = cL; cL = l_; vec4 e_ = hE##k; hE##k = cE; cE = e_; vec4 f_ = hF##k; hF##k = cF; cF = f_; VRC_CX_A(k) }
// Slot k takes slot k + 1 (k1); a later hit of `line` becomes kNoLine.
#define VRC_SHIFT(k, k1) hT##k = hT##k1; hN##k = hN##k1; hC##k = hC##k1; hL##k = hL##k1 == line ? kNoLine : hL##k1; hE##k = hE##k1; hF##k = hF##k1; VRC_SHIFT_A(k, k1)
#else
#define VRC_SLOT(k) float hT##k; vec3 hN##k; vec4 hC##k; uint hL##k; VRC_SLOT_A(k)
#define VRC_CX(k) if (cT < hT##k) { float t_ = hT##k; hT##k = cT; cT = t_; vec3 n_ = hN##k; hN##k = cN; cN = n_; vec4 c_ = hC##k; hC##k = cC; cC = c_; uint l_ = hL##k; hL##k = cL; cL = l_; VRC_CX_A(k) }
#define VRC_SHIFT(k, k1) hT##k = hT##k1; hN##k = hN##k1; hC##k = hC##k1; hL##k = hL##k1 == line ? kNoLine : hL##k1; VRC_SHIFT_A(k, k1)
#endif
VRC_SLOT(0)
#if VRC_SLOTS > 1
VRC_SLOT(1) VRC_SLOT(2) VRC_SLOT(3) VRC_SLOT(4) VRC_SLOT(5) VRC_SLOT(6) VRC_SLOT(7)
#endif
#if VRC_SLOTS != 1 && VRC_SLOTS != 8
#error "VRC_SLOTS: 1 or 8"
#endif
// Hits that passed the batch's filter, also those that did not fit the slots.
int hitCount = 0;
// The floor of a batch (main): the t of the last hit blended in this voxel and how many hits at
// exactly that t were blended (the first ones in test order); floorSeen counts the hits at the
// floor's t met by the current scan.
float floorT = 0.0;
uint floorCount = 0u, floorSeen = 0u;

void clearHits() {
    hitCount = 0;
    // Empty slots sort last.
    hT0 = uintBitsToFloat(0x7F800000u);
#if VRC_SLOTS > 1
    hT1 = hT0; hT2 = hT0; hT3 = hT0; hT4 = hT0; hT5 = hT0; hT6 = hT0; hT7 = hT0;
#endif
}

// Carries the new hit through the sorted slots (ties keep the earlier hit first, as a stable
// insertion sort); what is carried out of the last slot waits for the next batch (main).
void insertHit(float t, vec3 n, vec4 color, uint line, RoundedCone cone, float alpha) {
    float cT = t;
    vec3 cN = n;
    vec4 cC = color;
    uint cL = line;
#ifdef VRC_HIT_CONE
    vec4 cE = vec4(cone.x0, cone.r0), cF = vec4(cone.x1, cone.r1);
#endif
#if defined(TRANSPARENT) && defined(VRC_PATH_LENGTH_OPACITY)
    float cA = alpha;
#endif
    VRC_CX(0)
#if VRC_SLOTS > 1
    VRC_CX(1) VRC_CX(2) VRC_CX(3) VRC_CX(4) VRC_CX(5) VRC_CX(6) VRC_CX(7)
#endif
    ++hitCount;
}

// Removes slot 0 (the line `line` was blended) and marks the later hits of that line (each line is
// blended once per voxel, at its nearest hit).
void popHit(uint line) {
#if VRC_SLOTS > 1
    VRC_SHIFT(0, 1) VRC_SHIFT(1, 2) VRC_SHIFT(2, 3) VRC_SHIFT(3, 4) VRC_SHIFT(4, 5) VRC_SHIFT(5, 6) VRC_SHIFT(6, 7)
    hT7 = uintBitsToFloat(0x7F800000u);
#endif
}

// A later batch of the same voxel: a line with a hit at or before the floor (blended in an earlier
// batch) is not blended again.
void markBlendedLine(uint line) {
    if (hL0 == line) hL0 = kNoLine;
#if VRC_SLOTS > 1
    if (hL1 == line) hL1 = kNoLine;
    if (hL2 == line) hL2 = kNoLine;
    if (hL3 == line) hL3 = kNoLine;
    if (hL4 == line) hL4 = kNoLine;
    if (hL5 == line) hL5 = kNoLine;
    if (hL6 == line) hL6 = kNoLine;
    if (hL7 == line) hL7 = kNoLine;
#endif
}

#if defined(TRANSPARENT) && defined(VRC_PATH_LENGTH_OPACITY)
// Opacity that depends on the path length inside the tube: a tube of style alpha a is a
// homogeneous medium whose transmittance over a diameter is 1 - a, so over the ray's chord L it is
// (1 - a)^(L / 2r) (Beer-Lambert). The chord is the hit piece's rounded-cone interval (entry to
// exit; from the ray origin when the ray starts inside), r the mean of its two radii: a ray
// through the axis of a straight tube sees a, grazing rays less.
float pathLengthAlpha(float a, ConeInterval iv, RoundedCone cone) {
    if (a >= 1.0) return 1.0;
    float chord = max(iv.tOut - max(iv.tIn, 0.0), 0.0);
    float exponent = chord / (cone.r0 + cone.r1);
    return 1.0 - exp2(exponent * log2(1.0 - a));
}
#endif

#ifdef HALO
// style.halo (Everts et al. 2009, as Günther, Rössl & Theisel 2013, Sect. 4.2 draw their lines):
// the ring of haloFragment (shaders/transparent_fragment.glsl; CPU twin core/halo.h) on one piece,
// for a ray that misses its tube. tRing: where the ray meets the grown cone (entry, or exit when it
// starts inside) and nRing its normal there; key: the ray parameter of the ring's depth, which
// grows from the axis depth at the silhouette to HALO_DEPTH radii behind the axis at the ring's
// outer edge. False: no ring here.
bool vrcHaloHit(Ray ray, RoundedCone c, bool vertexA, bool vertexB, out float key, out float tRing, out vec3 nRing) {
    key = 0.0;
    tRing = 0.0;
    nRing = vec3(0.0);
    const float scale = 1.0 + HALO_WIDTH;
    ConeInterval ring = intersectRoundedCone(ray, RoundedCone(c.x0, c.r0 * scale, c.x1, c.r1 * scale));
    if (!ring.hit) return false;
    tRing = ring.tIn > 0.0 ? ring.tIn : ring.tOut;
    nRing = ring.tIn > 0.0 ? ring.nIn : ring.nOut;
    if (!(tRing > 0.0)) return false;
    // The ray's closest approach to the axis: as haloFragment, the middle of its chord through the
    // grown cone, except that a piece cut at a voxel face continues its segment's straight axis
    // there, so the approach is taken on the axis line and a ring whose approach lies past a face
    // end belongs to the piece on the other side (as the tubes' caps, testVoxel).
    vec3 axis = c.x1 - c.x0;
    float len2 = dot(axis, axis);
    vec3 mid = ray.origin + 0.5 * (ring.tIn + ring.tOut) * ray.dir;
    float s = len2 > 0.0 ? dot(mid - c.x0, axis) / len2 : 0.0;
    float along = len2 > 0.0 ? dot(ray.dir, axis) / sqrt(len2) : 1.0;
    if (abs(along) < 0.9999) {
        vec3 w0 = ray.origin - c.x0;
        float tLine = (along * dot(w0, axis) / sqrt(len2) - dot(w0, ray.dir)) / (1.0 - along * along);
        float sLine = dot(w0 + tLine * ray.dir, axis) / len2;
        if ((sLine < 0.0 && !vertexA) || (sLine > 1.0 && !vertexB)) return false;
        if (sLine >= 0.0 && sLine <= 1.0) {
            mid = ray.origin + tLine * ray.dir;
            s = sLine;
        }
    }
    s = clamp(s, 0.0, 1.0);
    vec3 q = c.x0 + s * axis;
    float radius = mix(c.r0, c.r1, s);
    float u = (distance(mid, q) - radius) / (HALO_WIDTH * radius);
    // Within the tube's radius: the tube of this line is entered nearby, not the ring.
    if (!(u >= 0.0)) return false;
    float depth = dot(q - uEye, uForward) + min(u, 1.0) * HALO_DEPTH * radius;
    if (!(depth > 0.0)) return false;
    key = uOrthographic ? depth : depth / dot(ray.dir, uForward);
    return true;
}
#endif

#ifdef HALO
// Rings whose key (pushed-back depth) lies past the voxel that finds them (the one holding their
// entry): carried along the ray, sorted by key, and composited when the march reaches the voxel
// holding the key, before that voxel's own hits (main). So a line at about the ring's depth shows
// through it, one behind is hidden, as in the exact paths; the order within the key's voxel is the
// one approximation. When the carry is full, a ring goes into the finding voxel's slots.
#define VRC_CARRY 4
float carryKey[VRC_CARRY];
vec3 carryNormal[VRC_CARRY];
vec4 carryColor[VRC_CARRY];  // HALO_COLOR, alpha
uint carryLine[VRC_CARRY];
int carryCount = 0;

bool carryRing(float key, vec3 n, vec4 color, uint line) {
    if (carryCount == VRC_CARRY) return false;
    int i = carryCount++;
    for (; i > 0 && carryKey[i - 1] > key; --i) {
        carryKey[i] = carryKey[i - 1];
        carryNormal[i] = carryNormal[i - 1];
        carryColor[i] = carryColor[i - 1];
        carryLine[i] = carryLine[i - 1];
    }
    carryKey[i] = key;
    carryNormal[i] = n;
    carryColor[i] = color;
    carryLine[i] = line;
    return true;
}
#endif

// Tests the pieces of voxel v against the ray; takes hits in [tEnter, tExit) (the current voxel).
// Collecting (mark false): hits past the floor (floorT, floorCount) go into the slots. Marking
// (mark true): the line of a hit at or before the floor is struck from the slots (markBlendedLine).
// Two passes per chunk of 32 pieces: the capsule pre-test of every piece records the passing ones
// in a bit mask, then the exact intersector and the hit path run for those only. On llvmpipe's
// 8-wide SIMD a branch runs whenever one lane takes it: with the pre-test inside the piece loop
// the intersector ran for ~35 % of the pieces (any of 8 lanes passing) although ~5 % pass
// (brain_2m: 427 pieces tested, 22.6 passing, 9.7 hits per ray); now it runs max-over-lanes of
// the candidates (docs/performance.md, "Design notes").
void testVoxel(Ray ray, ivec3 v, float tEnter, float tExit, bool mark) {
    if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, uGridSize))) return;
    uvec2 h = vrcHeaderAt((v.z * uGridSize.y + v.y) * uGridSize.x + v.x);
    uint count = h.y & kVrcCountMask;
    for (uint base = 0u; base < count; base += 32u) {
        uint n = min(count - base, 32u);
        uint candidates = 0u;
        for (uint k = 0u; k < n; ++k) {
            VrcPiece p = vrcPiece(h.x + base + k, v);
#ifdef HALO
            float rMax = max(p.cone.r0, p.cone.r1) * (1.0 + HALO_WIDTH) * 1.0001 + 1e-4 * uVoxelSize;
#else
            float rMax = max(p.cone.r0, p.cone.r1) * 1.0001 + 1e-4 * uVoxelSize;
#endif
            candidates |= uint(raySegmentDistance2(ray, tEnter, tExit, p.cone.x0, p.cone.x1) <= rMax * rMax) << k;
        }
        while (candidates != 0u) {
            uint k = uint(findLSB(candidates));
            candidates &= candidates - 1u;
            VrcPiece p = vrcPiece(h.x + base + k, v);
            ConeInterval iv = intersectRoundedCone(ray, p.cone);
#ifdef HALO
            if (!iv.hit) {
                // The ring of a piece whose tube the ray misses: taken in the voxel holding the
                // ring's entry, sorted at its pushed-back depth, unshaded (a negative alpha slot
                // marks it; main).
                float key, tRing;
                vec3 nRing;
                if (!vrcHaloHit(ray, p.cone, p.vertexA, p.vertexB, key, tRing, nRing)) continue;
                if (tRing < tEnter || tRing >= tExit) continue;
                bool ringPastFloor = key > floorT || (key == floorT && floorSeen++ >= floorCount);
                if (mark) {
                    if (!ringPastFloor) markBlendedLine(p.line);
                    continue;
                }
                if (!ringPastFloor) continue;
                if (key >= tExit) {
                    // Carried to the voxel of its key, found once: on the voxel's first batch.
                    if (floorT > 0.0 || carryRing(key, nRing, vec4(HALO_COLOR, p.color.a), p.line)) continue;
                }
                insertHit(key, nRing, vec4(HALO_COLOR, -1.0 - p.color.a), p.line, p.cone, p.color.a);
                continue;
            }
#else
            if (!iv.hit) continue;
#endif
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
            bool pastFloor = t > floorT || (t == floorT && floorSeen++ >= floorCount);
            if (mark) {
                if (!pastFloor) markBlendedLine(p.line);
                continue;
            }
            if (!pastFloor) continue;
#if defined(TRANSPARENT) && defined(VRC_PATH_LENGTH_OPACITY)
            insertHit(t, n, p.color, p.line, p.cone, pathLengthAlpha(p.color.a, iv, p.cone));
#else
            insertHit(t, n, p.color, p.line, p.cone, p.color.a);
#endif
        }
    }
}

// testVoxel over the current voxel, or with NEIGHBORS over its 3x3x3 block.
void testVoxels(Ray ray, ivec3 v, float tEnter, float tExit, bool mark) {
    floorSeen = 0u;
#ifdef NEIGHBORS
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) testVoxel(ray, v + ivec3(dx, dy, dz), tEnter, tExit, mark);
#else
    testVoxel(ray, v, tEnter, tExit, mark);
#endif
}

// The lighting of Kanzler et al. 2019 on the Eq. 1 density and the pieces (VRC_DENSITY_AO,
// VRC_PRECOMPUTED_AO, VRC_DENSITY_SHADOWS, VRC_HARD_TUBE_SHADOWS; vrcLighting below).
#include "vrc_lighting.glsl"

// end0, end1: the hit piece's (x0, r0), (x1, r1) (its own tube is excluded from the AO and
// shadow cones; unused without them).
vec3 shadeHit(Ray ray, float t, vec3 n, vec4 base, vec4 end0, vec4 end1, out float ao) {
    vec3 pos = ray.origin + t * ray.dir;
    vec3 facing = dot(n, ray.dir) <= 0.0 ? n : -n;
    ConeOwnTube own = coneOwnTube(end0, end1, base.a, base.a);
    ao = 1.0;
#ifdef AMBIENT_OCCLUSION
    ao = tubeAmbientOcclusion(pos, facing, own);
#endif
    float visibility = 1.0;
#ifdef SOFT_SHADOWS
    visibility = 1.0 - traceOcclusionCone(pos, uLightDir, uShadowTanHalfAperture, uShadowDistance, uShadowStrength,
                                          uShadowStartOffset, own);
#endif
#ifdef HARD_SHADOWS
    visibility = hardShadowVisibility(pos);
#endif
    vrcLighting(pos, n, facing, end0, end1, base.a, ao, visibility);
    return shadeBlinnPhong(base.rgb * ao, n, ray.dir, uLightDir, uLightTerms.x, uLightTerms.y * visibility,
                           uLightTerms.z * visibility, uLightTerms.w);
}

#ifdef HALO
// Composites the carried rings whose key lies before `limit` ("under", as main's hits).
void flushRings(Ray ray, float limit, inout vec4 accum, inout float firstDepth, inout vec3 firstNormal,
                inout uint firstLine, inout float firstAo) {
    int n = 0;
    while (n < carryCount && carryKey[n] < limit) {
        if (firstLine == kNoLine) {
            firstDepth = viewDepth(ray, carryKey[n]);
            firstNormal = carryNormal[n];
            firstLine = carryLine[n];
            firstAo = 1.0;
        }
        float a = carryColor[n].a;
        accum.rgb += (1.0 - accum.a) * a * carryColor[n].rgb;
        accum.a += (1.0 - accum.a) * a;
        ++n;
    }
    for (int i = n; i < carryCount; ++i) {
        carryKey[i - n] = carryKey[i];
        carryNormal[i - n] = carryNormal[i];
        carryColor[i - n] = carryColor[i];
        carryLine[i - n] = carryLine[i];
    }
    carryCount -= n;
}
#endif

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
        // The batches of the current voxel (see below): the floor (t = 0 before the first batch:
        // every hit has t > 0), and the marking visit.
        floorT = 0.0;
        floorCount = 0u;
        bool marking = false;
#ifdef VRC_LOD
        float lodStartT = vrcLodStartT();
#endif
#ifdef BRICK_SKIP
        ivec3 curBrick = ivec3(-1);
        bool curBrickEmpty = false;
#endif
        while (!done) {
#ifdef VRC_LOD
            // At a voxel boundary (not between two batches of one voxel): from here on the LoD
            // volume, if the footprint or the accumulated opacity asks for it.
            if (!marking && floorT == 0.0 && (tEnter >= lodStartT || accum.a >= uLodOpacityStart)) {
#ifdef HALO
                flushRings(ray, uintBitsToFloat(0x7F800000u), accum, firstDepth, firstNormal, firstLine, firstAo);
#endif
                vrcLodMarch(ray, tEnter, tFar, accum, firstDepth, firstNormal);
                break;
            }
#endif
#ifdef BRICK_SKIP
            // Empty space: jump over a whole empty brick (kBrick^3 voxels) to the first voxel past
            // its exit face, instead of stepping (and reading a header) voxel by voxel.
            ivec3 brick = v / kBrick;
            if (brick != curBrick) {  // one brick read per brick entered, not per voxel step
                curBrick = brick;
                curBrickEmpty = vrcBricks[(brick.z * uBrickGridSize.y + brick.y) * uBrickGridSize.x + brick.x] == 0u;
            }
            if (curBrickEmpty) {
                vec3 bLo = uGridOrigin + vec3(brick * kBrick) * uVoxelSize;
                vec3 bT = (bLo + vec3(stepDir + 1) * (0.5 * float(kBrick) * uVoxelSize) - ray.origin) * invDir;
                if (stepDir.x == 0) bT.x = 1e30;
                if (stepDir.y == 0) bT.y = 1e30;
                if (stepDir.z == 0) bT.z = 1e30;
                float tOut = min(min(bT.x, bT.y), bT.z);
                int axis = bT.x <= bT.y && bT.x <= bT.z ? 0 : (bT.y <= bT.z ? 1 : 2);
                vec3 g2 = (ray.origin + tOut * ray.dir - uGridOrigin) / uVoxelSize;
                ivec3 next = clamp(ivec3(floor(g2)), brick * kBrick, brick * kBrick + (kBrick - 1));
                next[axis] = stepDir[axis] > 0 ? (brick[axis] + 1) * kBrick : brick[axis] * kBrick - 1;
                v = next;
                for (int k = 0; k < 3; ++k) {
                    float face = uGridOrigin[k] + float(v[k] + (stepDir[k] > 0 ? 1 : 0)) * uVoxelSize;
                    tMax[k] = stepDir[k] == 0 ? 1e30 : (face - ray.origin[k]) * invDir[k];
                }
                tEnter = max(tEnter, tOut);
                done = any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, uGridSize)) || tEnter > tFar;
                continue;
            }
#endif
            float tExit = min(min(tMax.x, tMax.y), tMax.z);
#ifdef HALO
            // A fresh voxel: the carried rings of this voxel and of the empty ones passed go first.
            if (!marking && floorT == 0.0 && carryCount > 0)
                flushRings(ray, tExit, accum, firstDepth, firstNormal, firstLine, firstAo);
#endif
            uint header = vrcHeaderCount((v.z * uGridSize.y + v.y) * uGridSize.x + v.x);
#ifdef NEIGHBORS
            bool occupied = (header & kVrcNeighbourhoodBit) != 0u;
#else
            bool occupied = (header & kVrcCountMask) != 0u;
#endif
            if (occupied) {
                // Batches of at most VRC_SLOTS hits in (t, piece index) order: a voxel with more
                // hits is visited again (continue without stepping) with the floor at the last hit
                // blended; a later batch takes a second visit (marking) that strikes the lines
                // blended in earlier batches before it is composited. One call site of testVoxels
                // (each call site inlines the whole intersection loop).
                if (!marking) clearHits();
                testVoxels(ray, v, tEnter, tExit, marking);
                if (!marking && floorT > 0.0 && hitCount > 0) {
                    marking = true;
                    continue;
                }
                marking = false;
                // Slot 0 is the nearest remaining hit (popHit shifts the slots); kNoLine marks a
                // farther hit of a line already blended in this voxel.
                int hits = min(hitCount, VRC_SLOTS);
                for (int i = 0; i < hits; ++i) {
                    uint line = hL0;
                    floorCount = hT0 == floorT ? floorCount + 1u : 1u;
                    floorT = hT0;
                    if (line != kNoLine) {
                        vec4 base = hC0;
                        float ao = 1.0;
                        vec3 rgb;
#ifdef HALO
                        if (base.a < 0.0) {
                            base.a = -1.0 - base.a;  // a ring (testVoxel): its colour as it is
                            rgb = base.rgb;
                        } else
#endif
                        {
#ifdef VRC_HIT_CONE
                            rgb = shadeHit(ray, hT0, hN0, base, hE0, hF0, ao);
#else
                            rgb = shadeHit(ray, hT0, hN0, base, vec4(0.0), vec4(0.0), ao);
#endif
                        }
                        if (firstLine == kNoLine) {
                            firstDepth = viewDepth(ray, hT0);
                            firstNormal = hN0;
                            firstLine = line;
                            firstAo = ao;
                        }
#ifdef TRANSPARENT
                        // As every transparent path: shaded colour clamped to [0, 1], blended "under".
#ifdef VRC_PATH_LENGTH_OPACITY
                        float a = hA0;
#else
                        float a = base.a;
#endif
                        accum.rgb += (1.0 - accum.a) * a * clamp(rgb, 0.0, 1.0);
                        accum.a += (1.0 - accum.a) * a;
#else
                        accum = vec4(rgb, 1.0);
#endif
                    }
                    popHit(line);
                }
#ifdef TRANSPARENT
                done = accum.a >= uOpacityThreshold;
                if (hitCount > VRC_SLOTS && !done) continue;  // the next batch of this voxel
#else
                done = hitCount > 0;
#endif
            }
            floorT = 0.0;
            floorCount = 0u;
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
#ifdef HALO
    // Rings whose key lies past the last voxel marched.
    flushRings(ray, uintBitsToFloat(0x7F800000u), accum, firstDepth, firstNormal, firstLine, firstAo);
#endif
    imageStore(uColor, pixel, accum);
    imageStore(uNormalDepth, pixel, vec4(firstNormal, firstDepth));
    imageStore(uId, pixel, uvec4(firstLine));
    imageStore(uAo, pixel, vec4(firstAo));
}
