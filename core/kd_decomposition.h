#pragma once
// The spatial decomposition of data-parallel rendering: a k-d tree that cuts all of space into N
// regions (core/region.h) holding about the same number of primitives, the front-to-back order of
// those regions for a camera, and the assignment of segments and particles to the regions whose
// ranks must hold them. No OpenGL, no MPI, no files (io/partition.h stores a decomposition).
//
// VTK has the same machinery in vtkPKdTree (VTK Filters/Parallel/vtkPKdTree.cxx): a parallel
// k-d tree over the cells of a vtkDataSet whose ViewOrderAllProcessesFromPosition and
// ViewOrderAllProcessesInDirection give the regions' visibility order from the same rule as
// viewOrderFromPosition / viewOrderInDirection below (vtkKdTree::__ViewOrderRegionsFromPosition,
// Common/DataModel/vtkKdTree.cxx: at each split, the child on the camera's side first). It is not
// used here because vtkPKdTree and vtkDistributedDataFilter work on vtkDataSet cells and either
// clip cells at the region boundaries or give each cell to one region plus ghost cells. tubecast
// needs neither: a tube segment must be DUPLICATED into every region its rounded cone can reach
// (each rank then keeps only the contributions whose entry point lies in its box, core/region.h),
// its polyline neighbours must come along for cap clipping, and a rank that reads its brick of a
// partitioned set (`tubecast partition`) must know the tree's order without MPI and without
// building a vtkDataSet of a billion segments. The tree itself is a few dozen lines on top of
// std::nth_element.
#include <cstdint>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/line_set.h"
#include "core/particle_set.h"
#include "core/region.h"

namespace tc {

// One node of the tree. A split node sends points with p[axis] < split to `lower` and the others
// (p[axis] >= split) to `upper`, matching RegionBox's half-open [lo, hi).
struct KdNode {
    int axis = -1;  // 0, 1, 2 (x, y, z) for a split; -1 for a leaf
    float split = 0.0f;
    int lower = -1, upper = -1;  // child node indices (split nodes)
    int region = -1;             // leaf: its region index
    bool leaf() const { return axis < 0; }
    friend bool operator==(const KdNode&, const KdNode&) = default;
};

class KdDecomposition {
public:
    // One region: all of space.
    KdDecomposition();

    // A tree of exactly `regionCount` (>= 1, any integer) regions over `points` (each of weight 1;
    // the vector is reordered in place and may be moved in). A node of n regions and m points is
    // split along the longest axis of its points' bounding box into floor(n/2) regions below and
    // ceil(n/2) above, at the matching quantile: the lower child gets round(m floor(n/2) / n)
    // points. With distinct coordinates along that axis the split is exact (the plane lies halfway
    // between the two points on either side of it); points tied at the quantile all go to the
    // upper child. A node without points (more regions than points, or ties) is split in the
    // middle of its box clamped to the data's bounds, along that box's longest axis. Deterministic: the
    // tree depends only on the set of points and regionCount, not on their order or the thread
    // count (the children are built in parallel with oneTBB).
    static KdDecomposition build(std::vector<glm::vec3> points, int regionCount);

    // A tree from its nodes (node 0 the root), as saved. Throws InputError "WHERE: nodes[I]: ..."
    // unless the nodes form one tree whose leaves number the regions 0..N-1 once each, every axis
    // is 0..2 and every split is finite and inside its node's box (so the regions tile space).
    static KdDecomposition fromNodes(std::vector<KdNode> nodes, const std::string& where);

    // {"regions": N, "nodes": [{"axis": "x", "split": 0.5, "lower": 1, "upper": 2}, {"region": 0},
    // ...]} (docs/formats.md, "Partitioned line sets"); splits are written exactly (a float as a
    // JSON double). fromJson throws InputError naming `where` and the key.
    nlohmann::json toJson() const;
    static KdDecomposition fromJson(const nlohmann::json& tree, const std::string& where);

    int regionCount() const { return int(m_boxes.size()); }
    const std::vector<KdNode>& nodes() const { return m_nodes; }
    // The region's box: half-open, faces on the outside of the tree infinite.
    const RegionBox& box(int region) const { return m_boxes.at(std::size_t(region)); }
    const std::vector<RegionBox>& boxes() const { return m_boxes; }

    // The one region whose box holds p.
    int regionOf(const glm::vec3& p) const;

    // The regions a CLOSED box [lo, hi] meets (lo[a] < region.hi[a] and hi[a] >= region.lo[a] on
    // every axis), ascending; into `out` (cleared), so hot loops reuse its storage.
    void regionsOverlapping(const Bounds& box, std::vector<int>& out) const;

    // Every region once, front to back: no ray from `eye` meets a region before one that comes
    // earlier in the list (at every split, the child on the eye's side first; an eye on the plane
    // counts as above it, as regionOf does). For perspective cameras; the order of
    // vtkPKdTree::ViewOrderAllProcessesFromPosition.
    std::vector<int> viewOrderFromPosition(const glm::vec3& eye) const;
    // The same for parallel rays travelling along `direction` (orthographic cameras): at every
    // split, the lower child first when direction[axis] >= 0. The order of
    // vtkPKdTree::ViewOrderAllProcessesInDirection.
    std::vector<int> viewOrderInDirection(const glm::vec3& direction) const;
    // From the eye (perspective) or along forward() (orthographic).
    std::vector<int> viewOrder(const Camera& camera) const;

    friend bool operator==(const KdDecomposition& a, const KdDecomposition& b) { return a.m_nodes == b.m_nodes; }

private:
    explicit KdDecomposition(std::vector<KdNode> nodes);  // nodes already checked
    std::vector<KdNode> m_nodes;
    std::vector<RegionBox> m_boxes;  // per region
};

// The point that places a segment: its midpoint. Computed the same way everywhere (build, owner,
// reloading a partitioned set), so the owner of a segment is the same bit for bit.
inline glm::vec3 segmentMidpoint(const glm::vec3& a, const glm::vec3& b) {
    return 0.5f * (a + b);
}

// Segment s of a line set joins vertices v and v + 1 with v = s + p, p its polyline: segments are
// numbered polyline by polyline in vertex order, the order of StyledLines::segmentVertices.
// One midpoint per segment, in that order: what build() decomposes for lines.
std::vector<glm::vec3> segmentMidpoints(const LineSet& lines);

// Per region, the ascending indices of the primitives assigned to it.
using RegionItems = std::vector<std::vector<std::uint32_t>>;

// Every segment goes to every region its rounded cone's bounding box meets: the box of the two
// end points grown by their radii (which holds the whole cone, core/rounded_cone.h), grown further
// by a slack of 1e-2 r + 1e-5 (|x|max + r) so that an entry point a renderer computes in float a
// few rounding errors outside the exact surface still finds its segment in that region. So the
// rank of region R holds every tube that can have an entry point in R. A segment well inside a
// region lands in that one only; one near or across boundaries in each region it reaches.
// `vertexRadii` has one radius per vertex (the
// styled radii); the uniform overload gives every vertex `radius`. Radii must be >= 0.
RegionItems assignSegments(const KdDecomposition& tree, const LineSet& lines, float radius);
RegionItems assignSegments(const KdDecomposition& tree, const LineSet& lines, std::span<const float> vertexRadii);

// Every particle to every region its sphere's bounding box (with the same slack) meets.
// `radii`: one per particle (e.g. ParticleSet::radii or the styled radii).
RegionItems assignParticles(const KdDecomposition& tree, const ParticleSet& particles, float radius);
RegionItems assignParticles(const KdDecomposition& tree, const ParticleSet& particles, std::span<const float> radii);

// The segments of `lines` that region `region` OWNS: those whose midpoint lies in its box. Every
// segment of the data has exactly one owner, and the owner is among its assigned regions (the
// midpoint lies in the segment's box). Sums over all ranks that must count each segment once
// (the AO density volume, counts in logs) use the owned segments; rendering uses all of them.
std::vector<std::uint32_t> ownedSegments(const KdDecomposition& tree, int region, const LineSet& lines);
// The particles whose centre lies in the region's box.
std::vector<std::uint32_t> ownedParticles(const KdDecomposition& tree, int region, const ParticleSet& particles);

// Where a polyline of an extracted region came from: the source polyline and the source's
// (global) index of its first vertex; its vertices are the source's firstVertex, firstVertex + 1,
// ... in order.
struct RunOrigin {
    std::uint64_t polyline = 0;
    std::uint64_t firstVertex = 0;
    friend bool operator==(const RunOrigin&, const RunOrigin&) = default;
};

struct RegionLines {
    LineSet lines;
    std::vector<RunOrigin> origins;  // per polyline of `lines`
};

// The line set a region's rank renders, from `segments` (ascending, as assignSegments gives them):
// each polyline is cut into runs of consecutive assigned segments, and every run is extended by
// ONE neighbour segment at each end where the source polyline continues. Cap clipping
// (core/cap_clipping.h) clips a segment at each joint with a plane that depends on the vertex
// beyond the joint; without the neighbour, the run's end segments would keep full round caps at a
// cut joint: a bead where the full tube has none, or an entry counted twice in a transparent
// frame. The added neighbour is not assigned, so its cone's box misses the region: its own wrong
// cap at the cut lies outside the region box, where no entry point of this rank counts. Runs of
// one polyline that are at most two segments apart are joined (the gap filled), which needs no
// more segments than two separate runs with their neighbours. Vertices keep all attributes, in
// source order; attribute min/max stay the SOURCE's (so automatic styling ranges are the same on
// every rank); bounds are the extracted positions'; velocity is kept.
RegionLines extractRegionLines(const LineSet& lines, std::span<const std::uint32_t> segments);

// Per segment of `lines` (numbered as segmentMidpoints numbers them), the tangent the
// rotation-minimising frame carries out of it along its polyline (transportTangent of
// core/tangent_frame.h, starting afresh at each polyline's first segment).
std::vector<glm::vec3> transportedTangents(const LineSet& lines);
// Per run of an extracted region (`origins`, from extractRegionLines on `lines`), the tangent its
// source polyline carries into the run's first segment (`transported`: transportedTangents of
// `lines`), 0 for a run that starts its polyline: StyledLines::incomingTangent of the region, so
// that the rank holding the run frames it as one process holding the whole polyline does.
std::vector<glm::vec3> incomingTangents(const LineSet& lines, std::span<const glm::vec3> transported,
                                        std::span<const RunOrigin> origins);

// The particles at `indices` with their radii, colours, attributes and provenance; attribute
// min/max stay the source's, bounds are the extracted positions'.
ParticleSet extractParticles(const ParticleSet& particles, std::span<const std::uint32_t> indices);

}  // namespace tc
