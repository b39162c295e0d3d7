#pragma once
// The voxel model of voxel-based line ray casting (VRC; Kanzler, Rautenhaus & Westermann 2019):
// a view-independent grid in which every polyline is clipped at voxel faces into per-voxel pieces,
// so a ray that walks the grid front to back meets the line pieces in visibility order without
// sorting fragments. Built on the CPU with oneTBB; gl/vrc_renderer.h uploads it and ray-casts it
// (shaders/vrc_raycast.comp, whose decoding is the GPU twin of decodeEnd / decodePiece below).
//
// Pieces. A polyline is walked segment by segment through the grid (3D DDA); each maximal run of
// the polyline inside one voxel becomes one straight piece from the point where it enters the voxel
// to the point where it leaves it, both on the voxel's faces. The paper drops the first and last
// partial piece of each polyline (the part between the end vertex and the first face crossing);
// we keep them, clipped to the vertex: their vertex-side end is the polyline's end vertex, inside
// the voxel, coded as "face" kInteriorFace. A polyline that stays inside one voxel becomes one
// piece between its two end vertices. Radius and colour are interpolated linearly along the
// segment to the face hits; a piece carries its polyline id. Zero-length pieces (a crossing
// through a voxel edge or corner steps through a neighbour for no distance) are dropped.
//
// Quantization (quantization = q > 0). A face end point is snapped to the centre of one of
// q x q bins of its face and coded as (face id, 3 bits) << kBinBits | bin index, bin = v * q + u
// over the face's two in-plane axes in increasing axis order. Bins are laid out in absolute grid
// coordinates, so the two voxels sharing a face snap a crossing to the same point: pieces stay
// connected. A vertex end (kInteriorFace) is snapped to the centre of a cell of an m^3 lattice
// inside the voxel, m = min(q, kInteriorLattice), bin = (z * m + y) * m + x. quantization = 0
// keeps exact float end points (VrcExactPiece).
//
// Layout. One header per voxel (offset, count) and one linear piece array in which each voxel's
// pieces are contiguous, in voxel index order; within a voxel, pieces are in polyline order and
// along each polyline (the order is canonical, so any two builds of the same lines agree).
//
// Copies (VrcBuildOptions::dilate, what the renderer uses unless render.vrc.neighbors is on). A
// tube of radius r sticks out of the voxel holding its axis by up to r, and a ray tests only the
// pieces of the voxel it is in, so without help tubes are cut at voxel faces. dilateVrcModel puts
// a copy of each piece into every face/edge/corner neighbour its tube can reach: the voxel box
// grown by the piece's larger radius meets the piece's axis segment (a slab test; conservative,
// it over-includes only near the box's edges and corners). Near a joint with the next piece of
// the polyline (within one radius along the axis of a face end) the two tubes coincide (exactly
// for collinear pieces, up to the outer wedge at a bend), so only one of them is copied there:
// the axis is tested without its last radius before a face end b, and against the voxel across
// the face of a (the previous piece's home) also without its first radius. A copy keeps the home voxel's end codes
// and says where home is: 2 bits per axis (-1, 0, +1 as two's complement) in the top kOffsetBits
// of the polyline id field (quantized) or in info.z (exact). Tubes wider than a voxel are still
// cut one voxel out (as render.vrc.neighbors). Per voxel the pieces (home and copies) are in
// (home piece index, offset) order.
//
// LoD (Eq. 1 of the paper). Per voxel density = sum over the polyline parts inside it of
// length_i x opacity_i, in voxel lengths (the true polyline length, not the chord, with the
// opacity averaged along the part). Levels above average 2x2x2 blocks; odd sizes are padded with
// empty voxels (level size ceil(n / 2)), so mean x voxelCount x 8^level, i.e. the total of level
// 0, is conserved at every level.
//
// LoD volume (buildVrcLodVolume, what the ray caster samples with render.vrc.lod): Eq. 1 turned
// into an extinction coefficient. A tube of length l, radius r and opacity alpha, oriented at
// random, has a mean projected area of (pi / 2) r l (Cauchy: a quarter of its side surface), so a
// ray through a voxel of volume s^3 meets on average (pi / 2) r l d / s^3 such tubes over a path
// d; with the hits Poisson distributed the expected transmittance is exp(-alpha x that), i.e. the
// extinction coefficient sigma = (pi / 2) sum_i r_i l_i alpha_i / s^3: Eq. 1's length x opacity
// sum weighted by each line's projected width. Coarser levels average 2x2x2 blocks as the density
// pyramid (mean extinction; like every averaged pyramid it makes heterogeneous blocks more
// transparent than the mean of their transmittances).
#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/styled_lines.h"

namespace tc {

// End codes: face ids 0..5 are (axis * 2 + side), side 0 = the low face; 6 = a polyline vertex
// inside the voxel. 3 bits of face id above kBinBits bits of bin index.
inline constexpr std::uint32_t kInteriorFace = 6;
inline constexpr int kBinBits = 13;
inline constexpr std::uint32_t kBinMask = (1u << kBinBits) - 1u;
// Lattice of vertex ends per axis at most (16^3 = 4096 < 2^13).
inline constexpr int kInteriorLattice = 16;
// Largest quantization: q^2 bins must fit in kBinBits (90^2 = 8100 < 8192).
inline constexpr int kMaxQuantization = 90;
// A copy's home voxel offset (see Copies above): 2 bits per axis above kLineBits of polyline id.
inline constexpr int kLineBits = 26;
inline constexpr std::uint32_t kLineMask = (1u << kLineBits) - 1u;
// Offset bits of `home - storage` (components in -1..1), shifted to bit 0.
inline std::uint32_t encodeHomeOffset(glm::ivec3 d) {
    return std::uint32_t(d.x & 3) | (std::uint32_t(d.y & 3) << 2) | (std::uint32_t(d.z & 3) << 4);
}
inline glm::ivec3 decodeHomeOffset(std::uint32_t bits) {
    auto axis = [](std::uint32_t b) { return b == 3u ? -1 : int(b); };
    return {axis(bits & 3u), axis((bits >> 2) & 3u), axis((bits >> 4) & 3u)};
}

// 16 bytes per piece:
//   ends:   end A code in bits 0..15, end B code in bits 16..31 (face << 13 | bin);
//   line:   polyline id in bits 0..25, home voxel offset of a copy in bits 26..31 (see Copies);
//   color:  linear RGBA at the piece's middle, 8 bits per channel (packUnorm4x8 rounding);
//   radius: radius at end A and B as unorm16 fractions of VrcModel::maxRadius (bits 0..15, 16..31).
struct VrcCompactPiece {
    std::uint32_t ends;
    std::uint32_t line;
    std::uint32_t color;
    std::uint32_t radius;
};
static_assert(sizeof(VrcCompactPiece) == 16);

// 64 bytes per piece, quantization = 0: exact float end points (std430 layout of the shader's
// struct: vec4, vec4, vec4, uvec4).
struct VrcExactPiece {
    glm::vec4 a;  // xyz world position, w radius
    glm::vec4 b;
    glm::vec4 color;  // linear RGBA at the piece's middle, straight alpha
    glm::uvec4 info;  // x polyline id, y end flags (bit 0: a is a vertex end, bit 1: b), z home offset bits
                      // of a copy (encodeHomeOffset; 0 = the piece's own voxel), w 0
};
static_assert(sizeof(VrcExactPiece) == 64);

struct VrcVoxel {
    std::uint32_t offset;  // first piece
    std::uint32_t count;   // pieces; bit kNeighbourhoodBit: some voxel of the 3x3x3 block has pieces
};
inline constexpr std::uint32_t kNeighbourhoodBit = 0x80000000u;
inline constexpr std::uint32_t kCountMask = 0x7FFFFFFFu;

// A piece decoded to world space (both encodings decode to this).
struct VrcPiece {
    glm::vec3 a, b;
    float ra, rb;
    glm::vec4 color;
    std::uint32_t line;
    bool vertexA, vertexB;  // the end is a polyline end vertex (keeps its spherical cap)
    bool copy = false;      // a copy of a piece whose axis lies in a neighbouring voxel (dilateVrcModel)
};

struct VrcDensityLevel {
    glm::ivec3 size{0};
    std::vector<float> density;  // x fastest
    double total() const;
};

struct VrcModel {
    glm::ivec3 size{0};
    glm::vec3 origin{0.0f};
    float voxelSize = 0.0f;
    int quantization = 32;
    float maxRadius = 0.0f;
    std::vector<VrcVoxel> voxels;           // header, size.x * size.y * size.z, x fastest
    std::vector<VrcCompactPiece> compact;   // quantization > 0
    std::vector<VrcExactPiece> exact;       // quantization == 0
    std::vector<std::uint32_t> pieceVoxel;  // voxel index of each piece (for tests and LoD)
    std::vector<VrcDensityLevel> lod;       // Eq. 1 pyramid, lod[0] at the grid's resolution
    std::size_t clampedVertices = 0;        // vertices outside the grid (moved onto it)
    std::size_t copies = 0;                 // pieces that are copies (dilateVrcModel), included in pieceCount

    std::size_t voxelCount() const { return std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z); }
    std::size_t index(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(size.y) + std::size_t(y)) * std::size_t(size.x) + std::size_t(x);
    }
    glm::ivec3 coords(std::size_t i) const {
        return {int(i % std::size_t(size.x)), int(i / std::size_t(size.x) % std::size_t(size.y)),
                int(i / std::size_t(size.x) / std::size_t(size.y))};
    }
    std::size_t pieceCount() const { return quantization > 0 ? compact.size() : exact.size(); }
    std::size_t bytesPerPiece() const { return quantization > 0 ? sizeof(VrcCompactPiece) : sizeof(VrcExactPiece); }
    // What the GPU holds: header + pieces (the LoD pyramid is reported separately).
    std::size_t bytes() const { return voxelCount() * sizeof(VrcVoxel) + pieceCount() * bytesPerPiece(); }
    std::size_t lodBytes() const;

    // Piece `i` in world space.
    VrcPiece piece(std::size_t i) const;
};

struct VrcBuildOptions {
    int resolution = 128;   // voxels along the longest axis (>= 2), as makeDensityGrid
    int quantization = 32;  // 0 (exact) or 1..kMaxQuantization
    bool lod = true;        // build the Eq. 1 density pyramid
    bool dilate = false;    // copies into the neighbours a tube reaches (dilateVrcModel)
    float reach = 1.0f;     // with dilate: how far a piece reaches, in its radii (halos: core/halo.h haloReach)
};

// Builds the model. The grid is makeDensityGrid(lines.bounds, resolution)'s (cubic voxels, aspect
// kept, at least half a voxel of margin around the tubes' bounds). Runs tbb::parallel_for over
// polylines (counted, scanned, written at their offsets) and a parallel sort by (voxel, piece
// order); the result does not depend on the thread count. Throws tc::InputError if the model would
// exceed 2^31 pieces. Polylines are the vertex ranges from a FirstOfPolyline to a LastOfPolyline
// vertex (StyledLines keeps them contiguous).
VrcModel buildVrcModel(const StyledLines& lines, const VrcBuildOptions& options);

// Adds the copies (see Copies above) to a model without copies (the LoD pyramid is kept: it
// counts every piece once). `reach`: the radius factor of what a piece shows (style.halo's ring
// reaches 1 + its width times the tube's radius). Deterministic (tbb, order fixed by a sort on
// unique keys). Throws tc::InputError if a polyline id does not fit kLineBits or the model would
// exceed 2^31 pieces.
void dilateVrcModel(VrcModel& model, float reach = 1.0f);

// Recomputes the headers and neighbourhood bits from pieceVoxel (sorted by voxel).
void buildVrcHeaders(VrcModel& model);

// The model's grid and settings without any voxel content (sizes from makeDensityGrid): the
// common start of the CPU build above and the GPU build (gl/vrc_renderer.h).
VrcModel emptyVrcModel(const StyledLines& lines, const VrcBuildOptions& options);

// World position of end `code` of a piece in voxel `voxel` (q = the model's quantization > 0).
glm::vec3 decodeEnd(const VrcModel& model, glm::ivec3 voxel, std::uint32_t code);
// The code of world point `p` on face `face` (or inside, kInteriorFace) of `voxel`.
std::uint32_t encodeEnd(const VrcModel& model, glm::ivec3 voxel, std::uint32_t face, glm::vec3 p);

// Largest distance between a face end point and its snapped bin centre (half a bin diagonal), and
// between a vertex end and its lattice cell centre (half a cell diagonal), world units.
float vrcFaceQuantizationBound(const VrcModel& model);
float vrcVertexQuantizationBound(const VrcModel& model);

// One level of the ray caster's LoD volume (see LoD volume above).
struct VrcLodLevel {
    glm::ivec3 size{0};
    float voxelSize = 0.0f;        // world units: the model's voxel size x 2^level
    std::vector<glm::vec4> value;  // x fastest; rgb: colour x sigma (linear), a: sigma (per world unit)
    // Sum of sigma x voxel volume: the level's total projected line area x opacity (conserved
    // from level to level but for float rounding).
    double total() const;
};

// The LoD volume of `model` (its home pieces; copies are not counted), level 0 at the grid's
// resolution, each further level ceil(n / 2) per axis, down to one voxel. `opaque`: every tube
// has alpha 1 (the expected coverage of opaque tubes). Parallel over voxels (tbb), deterministic.
std::vector<VrcLodLevel> buildVrcLodVolume(const VrcModel& model, bool opaque);

// The Eq. 1 pyramid of `level0`: level L + 1 averages 2x2x2 blocks of level L, padded with zeros
// to even sizes, down to one voxel.
std::vector<VrcDensityLevel> buildDensityPyramid(VrcDensityLevel level0);

}  // namespace tc
