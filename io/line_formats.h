#pragma once
// The line formats tubecast parses itself, without VTK: TrackVis .trk, MRtrix .tck (with .tsf
// scalar files), Wavefront .obj line elements and tubecast's own binary .tcb. Layouts, coordinate
// conventions and limits are documented in docs/formats.md.
//
// The read* functions return the polylines as stored, NOT cleaned: NaN/Inf vertices are still
// there (cleanLineSet() removes and counts them), but the structure is valid: offsets ascend from
// 0 to the vertex count, every attribute has one value per vertex, fewer than 2^32 vertices.
// Malformed input throws InputError naming the file and the byte offset ("f.trk: byte 1004:
// track 0 declares 500 points (6000 bytes) but only 12 bytes are left") or, for the text formats,
// the line. No size field is trusted: counts are checked against the bytes actually present
// before anything is allocated from them. What a reader tolerates (a .tck `count` or .trk
// `n_count` that disagrees with the data, a .tck without its end marker, a TrackVis version 3
// header) is not an error but a warning in the source's ByteSource::warnings(), following what
// MRtrix and nibabel accept (docs/formats.md). A file of no tracks is a valid, empty LineSet.
#include <string>
#include <utility>
#include <vector>

#include "core/line_set.h"
#include "io/byte_source.h"

namespace tc {

// True for the extensions (lower-case, with the dot) handled here: .trk .tck .obj .tcb.
bool isNativeLineFormat(const std::string& extension);

// Reads a .trk, .tck (plus the .tsf files that belong to it, see findTsfFiles), .obj or .tcb
// file, chosen by extension. Not cleaned (see above). What the readers tolerated goes to
// `warnings` if given (ByteSource::warnings: "line 4: count: ..."; those of a .tsf start with its
// path).
LineSet readNativeLineFile(const std::string& path, std::vector<std::string>* warnings = nullptr);

// TrackVis .trk, header version 1 or 2, little- or big-endian (told apart by hdr_size == 1000).
// Per-point scalars become per-vertex attributes; per-track properties become per-vertex
// attributes constant along the track. Version 2 files with a non-zero vox_to_ras matrix are
// mapped from TrackVis "voxmm" coordinates to RAS mm: p_ras = vox_to_ras * (p / voxel_size - 0.5)
// (the convention of nibabel and DIPY); otherwise the voxmm coordinates are returned unchanged.
LineSet readTrk(const ByteSource& source);

// MRtrix .tck: text header ("mrtrix tracks", key: value lines, END), data in the same file
// ("file: . OFFSET"), Float32/Float64, LE/BE; a NaN triplet ends a track, an Inf triplet the file.
LineSet readTck(const ByteSource& source);

// MRtrix .tsf ("mrtrix track scalars"): one value per vertex of `tracks` (as returned by
// readTck, so in the same order); the track count and every track's length must match.
std::vector<float> readTsf(const ByteSource& source, const LineSet& tracks);

// The .tsf files that belong to the .tck at `tckPath`, with the attribute name each becomes,
// sorted by name: in the same directory, "STEM.tsf" -> "tsf" and "STEM_NAME.tsf",
// "STEM-NAME.tsf", "STEM.NAME.tsf" -> "NAME" (STEM: the .tck file name without extension). A
// .tsf that also matches a longer-stemmed .tck in that directory belongs to that one instead.
std::vector<std::pair<std::string, std::string>> findTsfFiles(const std::string& tckPath);

// Wavefront .obj polylines: "v x y z", "l i j k ..." (1-based, negative = relative, "i/t"
// takes per-vertex attributes from vt record t), "vt a b c ..." attribute rows (LineVis: the
// i-th vt row belongs to the i-th v when "l" gives no /t) and LineVis' "a NAME NAME ..."
// attribute names. Faces and everything else are ignored.
LineSet readObjLines(const ByteSource& source);

// tubecast's own binary format (.tcb, docs/formats.md): a header with counts and attribute
// names, then little-endian arrays that are read straight into the LineSet.
LineSet readTcb(const ByteSource& source);

// Writes `lines` as .tcb through an AtomicFile. Throws OutputError "PATH: cannot write: ...".
void writeTcb(const LineSet& lines, const std::string& path);
// The same bytes in memory (the line data a rank sends another in a data-parallel render); read
// them back with readTcb(MemorySource(...)).
std::vector<std::uint8_t> encodeTcb(const LineSet& lines);

}  // namespace tc
