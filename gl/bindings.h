#pragma once
// Every binding point the shaders use: shader storage buffers, the uniform buffer, the atomic
// counter, image units and texture units. C++ binds with the constants below; the shaders name the
// same points by the defines of kShaderBindings, which compileProgram prepends to every stage
// (gl/shader_library.h):
//     layout(std430, binding = SSBO_POSITION_RADIUS) readonly buffer PositionRadius { ... };
// A define is the constant's name in upper case with its kind in front (SSBO_, UBO_, ATOMIC_,
// IMAGE_, TEXTURE_). Points are shared between passes that never run in one program; within one
// program they must differ: the groups below say which programs read them together.
#include <initializer_list>
#include <string_view>

#include "gl/gl_api.h"

namespace tc::gl::binding {

// --- Shader storage buffers ----------------------------------------------------------------------
// The rasterized line programs (gl/line_geometry.h; shaders/line_buffers.glsl,
// segment_varyings.glsl, billboard_pass.comp); the VRC build (shaders/vrc_build.comp) reads the
// first three too. Every line program may add the transparency, opacity, culling and AO cache
// buffers further down, so none of those repeats a point of this group.
inline constexpr GLuint kPositionRadius = 0;
inline constexpr GLuint kVertexColors = 1;
inline constexpr GLuint kPolylineIds = 2;
inline constexpr GLuint kSegmentVertices = 3;
inline constexpr GLuint kBillboardCorners = 4;
inline constexpr GLuint kDrawOrder = 5;  // gl/segment_order.h
inline constexpr GLuint kVertexFlags = 6;
inline constexpr GLuint kSegmentRecords = 16;
// k-buffer (shaders/kbuffer_common.glsl).
inline constexpr GLuint kKBuffer = 7;
inline constexpr GLuint kKBufferHeaders = 17;
// Depth peeling (shaders/depth_peel.frag).
inline constexpr GLuint kPeelPrevious = 8;
inline constexpr GLuint kPeelCurrent = 9;
inline constexpr GLuint kPeelCandidates = 10;
// Opacity optimization's fragment lists (shaders/opacity_common.glsl); never with the k-buffer.
inline constexpr GLuint kVertexPartW = 11;
inline constexpr GLuint kListHeads = 12;
inline constexpr GLuint kFragmentDepths = 13;
inline constexpr GLuint kFragmentNext = 14;
inline constexpr GLuint kFragmentCounter = 15;
inline constexpr GLuint kFragmentParts = 17;
inline constexpr GLuint kFragmentFracs = 18;
inline constexpr GLuint kFragmentColors = 19;
// Hierarchical culling (shaders/hierarchical_culling.glsl, cull_pyramid.comp).
inline constexpr GLuint kCullPyramid = 20;
// The AO line cache (gl/ao_line_cache.h; shaders/ao_line_cache.glsl, ao_line_cache_build.comp).
inline constexpr GLuint kAoCache = 24;
inline constexpr GLuint kAoCacheSegments = 25;
inline constexpr GLuint kAoCacheOut = 26;

// Segment sort keys (gl/sort_keys.h; shaders/segment_sort_keys.comp), a pass of its own.
inline constexpr GLuint kSortPositionRadius = 0;
inline constexpr GLuint kSortSegmentVertices = 1;
inline constexpr GLuint kSortKeys = 2;
inline constexpr GLuint kSortSegmentIds = 3;
inline constexpr GLuint kSortOutsideCount = 4;

// GPU radix sort (gl/radix_sort.h): histogram, scan and scatter passes.
inline constexpr GLuint kRadixKeysIn = 0;
inline constexpr GLuint kRadixHistograms = 1;  // histogram pass output
inline constexpr GLuint kRadixValuesIn = 1;    // scatter pass
inline constexpr GLuint kRadixKeysOut = 2;
inline constexpr GLuint kRadixValuesOut = 3;
inline constexpr GLuint kRadixOffsets = 4;  // the scanned histograms, scatter pass
inline constexpr GLuint kScanData = 0;
inline constexpr GLuint kScanBlockSums = 1;

// Sphere glyphs (gl/sphere_renderer.h; shaders/sphere_billboard.vert) and their passes: sort keys
// (sphere_sort_keys.comp), voxelization (sphere_voxelize.comp, sphere_volume_resolve.comp) and
// the ambient cube (sphere_ambient_cache.comp).
inline constexpr GLuint kSphereCenterRadius = 0;
inline constexpr GLuint kSphereColors = 1;
inline constexpr GLuint kSphereIds = 2;
inline constexpr GLuint kSphereDrawOrder = 5;
inline constexpr GLuint kSphereAmbientCube = 6;
inline constexpr GLuint kSphereOversized = 7;  // POINTS programs
inline constexpr GLuint kSphereSortKeys = 2;
inline constexpr GLuint kSphereSortValues = 3;
inline constexpr GLuint kSphereAccumulator = 4;

// The VRC build (gl/vrc_renderer.h buildVrcModelGpu; shaders/vrc_build.comp, vrc_scan.comp,
// vrc_gather.comp) after kPositionRadius, kVertexColors and kPolylineIds.
inline constexpr GLuint kVrcPolylines = 3;
inline constexpr GLuint kVrcCounts = 4;
inline constexpr GLuint kVrcKeys = 5;
inline constexpr GLuint kVrcValues = 6;
inline constexpr GLuint kVrcRawPieces = 7;
inline constexpr GLuint kVrcRunEnd = 1;
inline constexpr GLuint kVrcGatheredPieces = 8;
inline constexpr GLuint kVrcPieceVoxel = 9;
// The VRC model, built (vrc_gather.comp) and ray cast (shaders/vrc_raycast.comp).
inline constexpr GLuint kVrcHeader = 0;
inline constexpr GLuint kVrcPieces = 1;       // block 0 of the piece array
inline constexpr GLuint kVrcPieceBlocks = 4;  // blocks 1 .. VrcRenderer::kMaxPieceBlocks - 1 at 4, 5, ...
inline constexpr GLuint kVrcShadowLines = 2;
inline constexpr GLuint kVrcBricks = 3;
inline constexpr GLuint kVrcLodStats = 11;  // samples per LoD level (VrcRenderer::enableLodStats)
// render.vrc.encoding "paper" (core/vrc_packed.h): the voxels' first piece indices take kVrcHeader,
// their 1-byte counts (four per word) this point.
inline constexpr GLuint kVrcPaperCounts = 12;

// --- Uniform buffers and atomic counters ---------------------------------------------------------
inline constexpr GLuint kFrameUniforms = 0;   // gl/frame_uniforms.h
inline constexpr GLuint kCulledSegments = 0;  // atomic counter of hierarchical culling

// --- Image units ---------------------------------------------------------------------------------
inline constexpr GLuint kMipSource = 0;        // shaders/density_mip.comp: level L
inline constexpr GLuint kMipTarget = 1;        // level L + 1
inline constexpr GLuint kSphereVolumeOut = 0;  // shaders/sphere_volume_resolve.comp
inline constexpr GLuint kVrcColor = 0;         // shaders/vrc_raycast.comp outputs
inline constexpr GLuint kVrcNormalDepth = 1;
inline constexpr GLuint kVrcId = 2;
inline constexpr GLuint kVrcAo = 3;
inline constexpr GLuint kVrcAoVolumeOut = 4;  // shaders/vrc_ao_precompute.comp

// --- Texture units -------------------------------------------------------------------------------
inline constexpr GLuint kGBufferAlbedo = 0;  // shaders/deferred_shading.frag
inline constexpr GLuint kGBufferNormalDepth = 1;
inline constexpr GLuint kVisibilitySegments = 2;  // deferred_shading.frag, surface_attributes.frag
inline constexpr GLuint kCullSource = 0;          // shaders/cull_pyramid.comp
inline constexpr GLuint kEarlyZAccumulated = 0;   // shaders/sphere_early_z.frag
// Units read beside the per-pass units above: the AO volumes (their samplers are set by
// uniform, gl/density_volume.h and gl/sphere_ambient.h) and the VRC pieces.
inline constexpr GLuint kDensityVolume = 8;    // shaders/cone_tracing.glsl uDensity
inline constexpr GLuint kSphereVolume = 9;     // shaders/sphere_ambient.glsl uSphereVolume
inline constexpr GLuint kVrcPieceTexels = 10;  // shaders/vrc_raycast.comp, VRC_PIECE_TEXTURE
inline constexpr GLuint kVrcEq1Density = 11;   // shaders/vrc_lighting.glsl uVrcDensity
inline constexpr GLuint kVrcAoVolume = 12;     // shaders/vrc_lighting.glsl uVrcAoVolume
inline constexpr GLuint kVrcLodVolume = 13;    // shaders/vrc_lod.glsl, the LoD atlas
inline constexpr GLuint kVrcGlobalIds = 14;    // shaders/vrc_raycast.comp, VRC_GLOBAL_IDS

// Points one program reads together must differ.
constexpr bool distinct(std::initializer_list<GLuint> points) {
    for (const GLuint* a = points.begin(); a != points.end(); ++a)
        for (const GLuint* b = a + 1; b != points.end(); ++b)
            if (*a == *b) return false;
    return true;
}
// A transparent line program: geometry, k-buffer or depth peeling, culling, AO cache.
static_assert(distinct({kPositionRadius, kVertexColors, kPolylineIds, kSegmentVertices, kBillboardCorners, kDrawOrder,
                        kVertexFlags, kSegmentRecords, kKBuffer, kKBufferHeaders, kPeelPrevious, kPeelCurrent,
                        kPeelCandidates, kCullPyramid, kAoCache, kAoCacheSegments, kAoCacheOut}));
// The opacity optimization's list pass.
static_assert(distinct({kPositionRadius, kVertexColors, kPolylineIds, kSegmentVertices, kBillboardCorners, kDrawOrder,
                        kVertexFlags, kSegmentRecords, kVertexPartW, kListHeads, kFragmentDepths, kFragmentNext,
                        kFragmentCounter, kFragmentParts, kFragmentFracs, kFragmentColors}));
static_assert(distinct({kSphereCenterRadius, kSphereColors, kSphereIds, kSphereDrawOrder, kSphereAmbientCube,
                        kSphereOversized}));
static_assert(distinct({kRadixKeysIn, kRadixValuesIn, kRadixKeysOut, kRadixValuesOut, kRadixOffsets}));
static_assert(distinct({kPositionRadius, kVertexColors, kPolylineIds, kVrcPolylines, kVrcCounts, kVrcKeys, kVrcValues,
                        kVrcRawPieces}));
static_assert(distinct({kVrcHeader, kVrcRunEnd, kVrcKeys, kVrcValues, kVrcRawPieces, kVrcGatheredPieces,
                        kVrcPieceVoxel}));
// The ray caster: the piece blocks take kVrcPieceBlocks .. kVrcPieceBlocks + 6.
static_assert(distinct({kVrcHeader, kVrcPieces, kVrcShadowLines, kVrcBricks, kVrcLodStats, kVrcPaperCounts}) &&
              kVrcPieceBlocks > kVrcBricks && kVrcLodStats > kVrcPieceBlocks + 6);
static_assert(distinct({kGBufferAlbedo, kGBufferNormalDepth, kVisibilitySegments, kDensityVolume, kSphereVolume,
                        kVrcPieceTexels, kVrcEq1Density, kVrcAoVolume, kVrcLodVolume, kVrcGlobalIds}));

}  // namespace tc::gl::binding

namespace tc::gl {

struct ShaderBinding {
    std::string_view define;  // the name the shaders use
    GLuint point;
};

// The bindings above under the names the shaders use; compileProgram defines each as its point.
inline constexpr ShaderBinding kShaderBindings[] = {
    {"SSBO_POSITION_RADIUS", binding::kPositionRadius},
    {"SSBO_VERTEX_COLORS", binding::kVertexColors},
    {"SSBO_POLYLINE_IDS", binding::kPolylineIds},
    {"SSBO_SEGMENT_VERTICES", binding::kSegmentVertices},
    {"SSBO_BILLBOARD_CORNERS", binding::kBillboardCorners},
    {"SSBO_DRAW_ORDER", binding::kDrawOrder},
    {"SSBO_VERTEX_FLAGS", binding::kVertexFlags},
    {"SSBO_SEGMENT_RECORDS", binding::kSegmentRecords},
    {"SSBO_KBUFFER", binding::kKBuffer},
    {"SSBO_KBUFFER_HEADERS", binding::kKBufferHeaders},
    {"SSBO_PEEL_PREVIOUS", binding::kPeelPrevious},
    {"SSBO_PEEL_CURRENT", binding::kPeelCurrent},
    {"SSBO_PEEL_CANDIDATES", binding::kPeelCandidates},
    {"SSBO_VERTEX_PART_W", binding::kVertexPartW},
    {"SSBO_LIST_HEADS", binding::kListHeads},
    {"SSBO_FRAGMENT_DEPTHS", binding::kFragmentDepths},
    {"SSBO_FRAGMENT_NEXT", binding::kFragmentNext},
    {"SSBO_FRAGMENT_COUNTER", binding::kFragmentCounter},
    {"SSBO_FRAGMENT_PARTS", binding::kFragmentParts},
    {"SSBO_FRAGMENT_FRACS", binding::kFragmentFracs},
    {"SSBO_FRAGMENT_COLORS", binding::kFragmentColors},
    {"SSBO_CULL_PYRAMID", binding::kCullPyramid},
    {"SSBO_AO_CACHE", binding::kAoCache},
    {"SSBO_AO_CACHE_SEGMENTS", binding::kAoCacheSegments},
    {"SSBO_AO_CACHE_OUT", binding::kAoCacheOut},
    {"SSBO_SORT_POSITION_RADIUS", binding::kSortPositionRadius},
    {"SSBO_SORT_SEGMENT_VERTICES", binding::kSortSegmentVertices},
    {"SSBO_SORT_KEYS", binding::kSortKeys},
    {"SSBO_SORT_SEGMENT_IDS", binding::kSortSegmentIds},
    {"SSBO_SORT_OUTSIDE_COUNT", binding::kSortOutsideCount},
    {"SSBO_RADIX_KEYS_IN", binding::kRadixKeysIn},
    {"SSBO_RADIX_HISTOGRAMS", binding::kRadixHistograms},
    {"SSBO_RADIX_VALUES_IN", binding::kRadixValuesIn},
    {"SSBO_RADIX_KEYS_OUT", binding::kRadixKeysOut},
    {"SSBO_RADIX_VALUES_OUT", binding::kRadixValuesOut},
    {"SSBO_RADIX_OFFSETS", binding::kRadixOffsets},
    {"SSBO_SCAN_DATA", binding::kScanData},
    {"SSBO_SCAN_BLOCK_SUMS", binding::kScanBlockSums},
    {"SSBO_SPHERE_CENTER_RADIUS", binding::kSphereCenterRadius},
    {"SSBO_SPHERE_COLORS", binding::kSphereColors},
    {"SSBO_SPHERE_IDS", binding::kSphereIds},
    {"SSBO_SPHERE_DRAW_ORDER", binding::kSphereDrawOrder},
    {"SSBO_SPHERE_AMBIENT_CUBE", binding::kSphereAmbientCube},
    {"SSBO_SPHERE_OVERSIZED", binding::kSphereOversized},
    {"SSBO_SPHERE_SORT_KEYS", binding::kSphereSortKeys},
    {"SSBO_SPHERE_SORT_VALUES", binding::kSphereSortValues},
    {"SSBO_SPHERE_ACCUMULATOR", binding::kSphereAccumulator},
    {"SSBO_VRC_POLYLINES", binding::kVrcPolylines},
    {"SSBO_VRC_COUNTS", binding::kVrcCounts},
    {"SSBO_VRC_KEYS", binding::kVrcKeys},
    {"SSBO_VRC_VALUES", binding::kVrcValues},
    {"SSBO_VRC_RAW_PIECES", binding::kVrcRawPieces},
    {"SSBO_VRC_RUN_END", binding::kVrcRunEnd},
    {"SSBO_VRC_GATHERED_PIECES", binding::kVrcGatheredPieces},
    {"SSBO_VRC_PIECE_VOXEL", binding::kVrcPieceVoxel},
    {"SSBO_VRC_HEADER", binding::kVrcHeader},
    {"SSBO_VRC_PIECES", binding::kVrcPieces},
    {"SSBO_VRC_PIECE_BLOCKS", binding::kVrcPieceBlocks},
    {"SSBO_VRC_SHADOW_LINES", binding::kVrcShadowLines},
    {"SSBO_VRC_BRICKS", binding::kVrcBricks},
    {"SSBO_VRC_LOD_STATS", binding::kVrcLodStats},
    {"SSBO_VRC_PAPER_COUNTS", binding::kVrcPaperCounts},
    {"UBO_FRAME_UNIFORMS", binding::kFrameUniforms},
    {"ATOMIC_CULLED_SEGMENTS", binding::kCulledSegments},
    {"IMAGE_MIP_SOURCE", binding::kMipSource},
    {"IMAGE_MIP_TARGET", binding::kMipTarget},
    {"IMAGE_SPHERE_VOLUME_OUT", binding::kSphereVolumeOut},
    {"IMAGE_VRC_COLOR", binding::kVrcColor},
    {"IMAGE_VRC_NORMAL_DEPTH", binding::kVrcNormalDepth},
    {"IMAGE_VRC_ID", binding::kVrcId},
    {"IMAGE_VRC_AO", binding::kVrcAo},
    {"IMAGE_VRC_AO_VOLUME", binding::kVrcAoVolumeOut},
    {"TEXTURE_GBUFFER_ALBEDO", binding::kGBufferAlbedo},
    {"TEXTURE_GBUFFER_NORMAL_DEPTH", binding::kGBufferNormalDepth},
    {"TEXTURE_VISIBILITY_SEGMENTS", binding::kVisibilitySegments},
    {"TEXTURE_CULL_SOURCE", binding::kCullSource},
    {"TEXTURE_EARLY_Z_ACCUMULATED", binding::kEarlyZAccumulated},
    {"TEXTURE_DENSITY_VOLUME", binding::kDensityVolume},
    {"TEXTURE_SPHERE_VOLUME", binding::kSphereVolume},
    {"TEXTURE_VRC_PIECE_TEXELS", binding::kVrcPieceTexels},
    {"TEXTURE_VRC_LOD", binding::kVrcLodVolume},
    {"TEXTURE_VRC_GLOBAL_IDS", binding::kVrcGlobalIds},
};

}  // namespace tc::gl
