#pragma once
// The paper's compact encoding of the VRC voxel model (Kanzler, Rautenhaus & Westermann 2019,
// Sec. 3.2 and Sec. 6.2, Table I): a 5-byte header per voxel and 4-6 bytes per piece, packed from
// a built quantized model (core/vrc_model.h; the CPU and the GPU build both give a VrcModel).
// render.vrc.encoding: "paper" selects it (gl/vrc_renderer.h; shaders/vrc_raycast.comp VRC_PAPER
// is the GPU twin of unpackVrcPiece below); docs/scene-spec.md says where it differs from the paper.
//
// Header: per voxel the index of its first piece (4 bytes, `offsets`) and its piece count
// (`counts`): 1 byte (at most 255 pieces per voxel, as the paper), or 2 bytes in a model where
// some voxel holds more (a 6-byte header; the paper's data sets never needed it, dense fiber
// bundles do).
//
// Piece: a bit string of `bitsPerPiece` bits, least significant bit first, rounded up to whole
// bytes; piece i starts at byte i x bytesPerPiece of `bytes`. Fields in order:
//   end A, end B   endBits each: face id (3 bits) above 2 x ceil(log2 q) bits of bin (the
//                  paper's end code). Face ends (ids 0..5) keep the model's bin (v * q + u), so
//                  they decode bit-identically to the 16-byte model's. The paper has no vertex
//                  ends (it drops a polyline's first and last partial piece); ours (the model's
//                  kInteriorFace) take face ids 6 and 7: a cell of an m'^3 lattice inside the
//                  voxel, index (z * m' + y) * m' + x, whose high bit is the face id's low bit.
//                  m' = the largest m' <= min(q, kInteriorLattice) with m'^3 <= 2^(2 ceil(log2 q) + 1)
//                  (vrcPaperInteriorLattice): the 16-byte model's lattice from q = 33 on; below
//                  it coarser (q = 32: 12 instead of 16), and a vertex end is re-snapped from the
//                  model's cell centre to the centre of the m' cell holding it.
//   colour         8 bits: index into a per-model palette of 256 RGBA8 colours (the paper's
//                  "1 byte per line that maps to colour/transparency"); exact when the pieces
//                  have at most 256 distinct colours, else a median cut (vrcPaperPalette).
//   local line     5 bits: the index of the piece's polyline among the distinct polylines of its
//                  storage voxel, in order of first appearance (the paper's local line ID). The
//                  ray caster compares line ids only within one voxel (a line is blended once per
//                  voxel), which this id serves; the id image needs global ids (globalIds). A
//                  model with a voxel of more than 32 polylines widens the field for all pieces
//                  to ceil(log2(most polylines in a voxel)) bits, at most kPaperMaxLineBits.
//   home offset    6 bits, only in a model with copies (dilateVrcModel): the 16-byte model's
//                  top 6 bits of the line field (core/vrc_model.h, Copies).
//   radius         0 bits when every piece end has the same radius (the paper's single user
//                  radius; kept once, `constantRadius`), else 16 bits: the radius at end A and B
//                  as unorm8 of maxRadius (two per piece, not one: the two pieces at a joint then
//                  agree on the radius there, and tapered tubes keep their taper).
// Bits at q = 4, 8 | 16, 32 | 64 without copies and with one radius: 27, 31 | 35, 39 | 43, i.e.
// 4 | 5 | 6 bytes, Table I's (4, 8) | (16, 32) | (64, 128) rows; copies add 6 bits (q = 32: 45
// bits, 6 bytes; with an 8-bit local line 48 bits, still 6 bytes).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vrc_model.h"

namespace tc {

inline constexpr int kPaperLineBits = 5;      // the paper's local line id
inline constexpr int kPaperMaxLineBits = 12;  // widened: the ray caster reads a piece from 3 words (<= 9 bytes)
inline constexpr int kPaperMaxPiecesPerVoxel = 65535;  // a 2-byte count
inline constexpr int kPaperColorBits = 8;
inline constexpr int kPaperOffsetBits = 6;
inline constexpr int kPaperRadiusBits = 16;  // when the radii vary (two unorm8)

// The field widths of the packed layout for quantization q (1..kMaxQuantization).
struct VrcPaperLayout {
    int quantization = 0;
    int binBits = 0;          // 2 x ceil(log2 q)
    int endBits = 0;          // 3 + binBits
    int interiorLattice = 0;  // m' (see the file comment)
    bool copies = false;      // the home offset field is present
    bool radiusVaries = false;
    int lineBits = kPaperLineBits;  // kPaperLineBits..kPaperMaxLineBits
    int countBytes = 1;             // per voxel header count: 1 or 2
    int bitsPerPiece() const {
        return 2 * endBits + kPaperColorBits + lineBits + (copies ? kPaperOffsetBits : 0) +
               (radiusVaries ? kPaperRadiusBits : 0);
    }
    int bytesPerPiece() const { return (bitsPerPiece() + 7) / 8; }
    // Bit offsets of the fields after the two ends.
    int colorShift() const { return 2 * endBits; }
    int lineShift() const { return colorShift() + kPaperColorBits; }
    int offsetShift() const { return lineShift() + lineBits; }
    int radiusShift() const { return offsetShift() + (copies ? kPaperOffsetBits : 0); }
};
VrcPaperLayout vrcPaperLayout(int quantization, bool copies, bool radiusVaries, int lineBits = kPaperLineBits,
                              int countBytes = 1);
int vrcPaperInteriorLattice(int quantization);

// A palette of at most 256 RGBA8 colours (packUnorm4x8 order: r in bits 0..7) for a list of
// colours, and each input colour's index. Exact (every colour its own entry) when there are at
// most 256 distinct colours; else median cut (Heckbert 1982) over the distinct colours weighted by
// how often each occurs: the box with the widest channel range is split at the weighted median of
// that channel until there are 256 boxes, and an entry is its box's weighted mean. Written here
// rather than taken from a library: the project has no image-quantization dependency, and the
// ray caster needs a deterministic palette (the sorts are by total orders, no threads).
struct VrcPalette {
    std::vector<std::uint32_t> colors;  // at most 256 entries
    std::vector<std::uint8_t> index;    // per input colour
    bool exact = true;
    int maxError = 0;  // largest |channel - palette channel| over the inputs, in 1/255
};
VrcPalette vrcPaperPalette(const std::vector<std::uint32_t>& colors);

struct VrcPackedModel {
    VrcPaperLayout layout;
    glm::ivec3 size{0};
    glm::vec3 origin{0.0f};
    float voxelSize = 0.0f;
    float maxRadius = 0.0f;
    std::uint32_t constantRadius = 0;    // the unorm16 radius code (of maxRadius) of every end, when !radiusVaries
    std::vector<std::uint32_t> palette;  // 256 entries (unused ones 0)
    int paletteSize = 0;
    bool paletteExact = true;
    int paletteMaxError = 0;               // in 1/255
    std::vector<std::uint32_t> offsets;    // per voxel: first piece
    std::vector<std::uint16_t> counts;     // per voxel: pieces (< 2^(8 countBytes))
    std::vector<std::uint8_t> bytes;       // pieceCount x bytesPerPiece, then zero padding to a multiple of 4 + 8
    std::vector<std::uint32_t> globalIds;  // per piece: the polyline id (the id image; not part of the encoding)
    std::size_t pieceCount = 0;

    std::size_t headerBytes() const { return offsets.size() * std::size_t(4 + layout.countBytes); }
    // The counts as the ray caster reads them: 4 (1-byte counts) or 2 per little-endian word.
    std::vector<std::uint32_t> countWords() const;
    std::size_t pieceBytes() const { return pieceCount * std::size_t(layout.bytesPerPiece()); }
    std::size_t bytesTotal() const { return headerBytes() + pieceBytes(); }
    // The packed bytes as little-endian 32-bit words (what the ray caster reads).
    std::vector<std::uint32_t> words() const;
};

// The packed model, or why the model cannot be packed (`reason` not empty; the renderer then keeps
// the 16-byte encoding): quantization 0 (exact ends), a voxel with more than 65535 pieces or more
// than 2^kPaperMaxLineBits distinct polylines.
struct VrcPackResult {
    VrcPackedModel model;
    std::string reason;
    std::size_t widePieces = 0;     // voxels with more than 255 pieces (the 2-byte count)
    std::size_t wideLines = 0;      // voxels with more than 32 distinct polylines (a wider local id)
    std::size_t tooManyPieces = 0;  // voxels with more than kPaperMaxPiecesPerVoxel pieces
    std::size_t tooManyLines = 0;   // voxels with more than 2^kPaperMaxLineBits distinct polylines
    bool ok() const { return reason.empty(); }
};
// Parallel over voxels (tbb); deterministic.
VrcPackResult packVrcModel(const VrcModel& model);

// Piece `i` (stored in voxel `voxel`) in world space, as the ray caster decodes it; `line` is the
// local line id (globalIds[i] holds the global one).
VrcPiece unpackVrcPiece(const VrcPackedModel& packed, std::size_t voxel, std::size_t i);
// The raw fields of piece i: end codes in the paper layout, palette index, local line, home offset
// bits, radius bits.
struct VrcPaperFields {
    std::uint32_t endA, endB, color, line, offset, radius;
};
VrcPaperFields vrcPaperFields(const VrcPackedModel& packed, std::size_t i);

// Largest distance between a vertex end of the packed model and the same end of the 16-byte model
// (0 when the lattices agree): half a diagonal of an m' cell, the re-snap of the model's cell centre.
float vrcPaperVertexResnapBound(const VrcPackedModel& packed);

}  // namespace tc
