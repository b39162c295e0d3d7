#pragma once
// Line sets from VTK files: legacy .vtk (ASCII or binary; POLYDATA or UNSTRUCTURED_GRID),
// XML .vtp (PolyData) and XML .vtu (UnstructuredGrid), and ParaView's partitioned XML files
// .pvtp / .pvtu (a header naming the .vtp / .vtu pieces).
#include <string>

#include "core/line_set.h"
#include "core/particle_set.h"

namespace tc {

// Reads the polylines of a VTK file, chosen by extension (case-insensitive): .vtk, .vtp, .vtu,
// .pvtp, .pvtu (every piece, appended in the order the file lists them).
// The non-VTK formats .trk, .tck (+ .tsf), .obj and .tcb go to io/line_formats.h (their errors
// name the byte offset or line); cleaning and the checks below apply to them too.
//
// - Polylines come from VTK_POLY_LINE and VTK_LINE cells (the Lines cell array of PolyData; the
//   line and polyline cells of an UnstructuredGrid), in file order, one LineSet polyline per
//   cell. Consecutive 2-point VTK_LINE cells are NOT merged into longer polylines: a file of
//   segments renders correctly but gets round caps at every joint.
// - Every numeric point-data array becomes per-vertex Attributes (as float): a 1-component
//   array under its name, an n-component one as name_x, name_y, name_z (name_3, name_4, ...
//   beyond three) plus name_magnitude. Unnamed arrays are called "array<i>"; string arrays are
//   skipped. Vertices, polygons and other cells are ignored.
// - The result is passed through cleanLineSet(); what it removed goes to `report` if given, and
//   with it what the native readers tolerated (CleanReport::warnings, e.g. a stale .tck count).
// - A native file that stores no polylines (an empty .tck or .trk tractogram) is read as an empty
//   LineSet, not an error; loadDataset (io/dataset.h) is where an empty dataset is refused.
//
// Throws InputError, always starting with the path: "PATH: no such file", "PATH: unsupported
// file extension ...", "PATH: VTK: <the reader's first error>", "PATH: cell C: point id I out
// of range (N points)", "PATH: no polylines (N points, M cells of other types)" or
// "PATH: no polylines left after cleaning (<summary>)" (when there were some before). VTK's own
// error output is captured, not printed. Reads are serialised (VTK's output window is
// process-global).
LineSet readLineSet(const std::string& path, CleanReport* report = nullptr);

// .vtk, .vtp, .vtu, .pvtp or .pvtu (case-insensitive).
bool isVtkFile(const std::string& path);
// .pvtp or .pvtu (case-insensitive): a partitioned file whose pieces readLinePieces reads.
bool isPiecedVtkFile(const std::string& path);

// The polylines of share `share` of `shares` of a .pvtp / .pvtu file (VTK's UpdatePiece): of its P
// pieces a contiguous block (shares <= P: from share * P / shares up to (share + 1) * P / shares;
// more shares than pieces: one piece or none each), so the shares in order hold readLineSet's
// polylines in order (cleaned piece by piece, which cleans each polyline as the whole read
// does). Attribute ranges are the share's. A share without pieces is an empty LineSet without
// attributes. Errors as readLineSet's; a share whose
// pieces hold points but no polylines (particles) is refused: "PATH: share S of N: no polylines
// (K points): reading the pieces of a file in parallel takes line data only".
LineSet readLinePieces(const std::string& path, int share, int shares, CleanReport* report = nullptr);

// A VTK file holds either lines or particles: lines when it has line or polyline cells (read
// as readLineSet does), otherwise, when it has points (vertex cells or a bare point cloud, the
// way ParaView users save particles), every point as a particle. Point data becomes attributes
// as above, except that the first 1-component array named "radius" or "radii" (any case) gives
// the particles' radii (must be > 0) and the first unsigned-char array of 3 or 4 components
// (VTK's colour convention) their sRGB(A) colours.
struct VtkFileData {
    bool isPoints = false;
    LineSet lines;       // !isPoints
    ParticleSet points;  // isPoints
};
VtkFileData readVtkFile(const std::string& path, CleanReport* report = nullptr);

// Writes `lines` as VTK XML PolyData (.vtp): float points, one polyline cell per polyline,
// one float point-data array per attribute, binary appended data (raw, zlib-compressed).
// Written through an AtomicFile. Throws OutputError "PATH: cannot write: ...".
void writeLineSetVtp(const LineSet& lines, const std::string& path);

// Writes particles as VTK XML PolyData with one vertex cell per particle: a "radius" array and
// unsigned-char RGBA "colors" when the set carries them, one float array per attribute; what
// readVtkFile reads back as particles. Same encoding and errors as writeLineSetVtp.
void writeParticleSetVtp(const ParticleSet& particles, const std::string& path);

}  // namespace tc
