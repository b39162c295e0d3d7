#pragma once
// Partitioned line sets: a line set decomposed once by a k-d tree (core/kd_decomposition.h) into
// one brick per region, so that each rank of a data-parallel render reads only its own brick.
// `tubecast partition DATA -n N -o DIR` writes
//     DIR/index.json       format, version, the tree, each region's box, file names and counts,
//                          the source's counts, bounds and attribute ranges
//     DIR/region-K.tcb     region K's line set (extractRegionLines: the segments assigned to K
//                          in runs, with one joint neighbour at each cut) as a plain .tcb
//     DIR/region-K.runs    where each polyline of region-K.tcb came from (RunOrigin) and the
//                          tangent its source polyline carries into it (incomingTangents)
// (layout in docs/formats.md, "Partitioned line sets"). The bricks are written first and
// index.json last, each through an AtomicFile, so a directory with an index.json is complete.
//
// A segment near a boundary is in several bricks. Loading the set as a whole keeps each segment
// once, from the brick of the region that OWNS it: the region holding its midpoint (recomputed
// from the brick's positions with the stored tree, bit for bit as when it was written; see
// ownedSegments). The RunOrigins put every owned segment back at its source position, so the
// whole load is the source line set exactly: same polylines in the same order, same vertices
// and attribute values.
#include <cstdint>
#include <string>
#include <vector>

#include "core/kd_decomposition.h"
#include "core/line_set.h"

namespace tc {

inline constexpr int kPartitionVersion = 1;

struct PartitionBrick {
    std::string file;      // "region-K.tcb", in the index's directory
    std::string runsFile;  // "region-K.runs"
    RegionBox box;         // the tree's box of region K
    // Of the brick's line set: polylines (runs), vertices, segments; of those segments, how many
    // are assigned to the region (the rest are joint neighbours) and how many it owns.
    std::uint64_t polylines = 0, vertices = 0, segments = 0, assignedSegments = 0, ownedSegments = 0;
};

struct AttributeRange {
    std::string name;
    float min = 0, max = 0;  // NaN when the attribute has no finite value
};

struct PartitionIndex {
    std::string path;       // of index.json
    std::string directory;  // that holds it and the bricks
    std::string source;     // what was partitioned, as loadDataset named it
    KdDecomposition tree;
    // The largest tube radius the assignment covers: a rank holds every segment whose tube of
    // this radius can have an entry point in its region. Rendering with larger radii would lose
    // entries near region boundaries; partition again with a larger --radius.
    float radius = 0;
    std::uint64_t polylines = 0, vertices = 0, segments = 0;  // of the source
    Bounds bounds;                                            // of the source's positions
    std::vector<AttributeRange> attributes;                   // the source's, in order
    std::string velocity;                                     // LineSet::velocity of the source
    std::vector<PartitionBrick> bricks;                       // per region

    int regionCount() const { return tree.regionCount(); }
    std::string brickPath(int region) const;  // directory / bricks[region].file
};

// Assigns `lines` to the regions of `tree` for tubes of radius up to `radius`, writes the bricks
// and index.json into `directory` (which must exist) and returns the index. `source` names the
// data in index.json. Existing files of the same names are replaced. Throws OutputError
// "PATH: cannot write: ...".
PartitionIndex writePartition(const LineSet& lines, const KdDecomposition& tree, float radius,
                              const std::string& source, const std::string& directory);

// True for a directory holding an index.json, and for a .json file whose "format" is
// "tubecast-partition" (a scene .json is not). Never throws: unreadable files are not partitions.
bool isPartitionPath(const std::string& path);

// Reads and checks index.json (`path` is the file or its directory). Throws InputError naming the
// file and key: "DIR/index.json: version: unsupported partition version 2 (this build reads
// version 1)", "DIR/index.json: regions[3].box: does not match region 3 of the tree", ...
PartitionIndex readPartitionIndex(const std::string& path);

// Region `region`'s brick alone: its line set as written (whole runs with their joint
// neighbours), attribute min/max set to the SOURCE's ranges (automatic styling ranges are then the
// same on every rank), bounds of its own positions, the source's velocity. `origins`, when given,
// receives the RunOrigin of each polyline (reads region-K.runs too), and `tangents` (only with
// `origins`) each polyline's incoming tangent (core/kd_decomposition.h; empty from a runs file of
// version 1, which has none). Throws InputError naming the
// brick: "DIR/region-3.tcb: no such file", "DIR/region-3.tcb: 1200 vertices, index.json says
// 1300", a .tcb format error, an attribute list that differs from the index's.
LineSet readPartitionRegion(const PartitionIndex& index, int region, std::vector<RunOrigin>* origins = nullptr,
                            std::vector<glm::vec3>* tangents = nullptr);

// Every brick and its runs, each segment kept once (from its owner's brick), reassembled into the
// source line set (see the top of this file). Throws InputError naming the file for a missing or
// malformed brick or runs file and for counts that do not add up to the index's.
LineSet readPartitionWhole(const PartitionIndex& index);

}  // namespace tc
