#include "core/kd_decomposition.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/parallel_chunks.h"
#include "core/spec_reader.h"
#include "core/tangent_frame.h"

namespace tc {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
const char* const kAxisNames[3] = {"x", "y", "z"};

// Below this many points a node's children are built on the calling thread: spawning costs more
// than the nth_element of a few thousand points.
constexpr std::size_t kParallelBuildPoints = 1 << 16;

int longestAxis(const glm::vec3& extent) {
    int axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    return axis;
}

Bounds boundsOf(const glm::vec3* points, std::size_t n) {
    return reduceChunks(
        std::int64_t(n), Bounds{},
        [&](std::int64_t begin, std::int64_t end, Bounds& b) {
            for (std::int64_t i = begin; i < end; ++i) b.extend(points[i]);
        },
        [](Bounds a, const Bounds& b) {
            if (!b.empty()) {
                a.extend(b.lo);
                a.extend(b.hi);
            }
            return a;
        });
}

// Builds the subtree of `regions` regions at nodes[node] over the points [begin, end) inside
// `box`. A subtree of n regions has 2n - 1 nodes, so child indices follow from the region counts
// and both children can be built at once without sharing a counter.
struct TreeBuilder {
    std::vector<KdNode>& nodes;
    Bounds data;  // of all points; the fallback extent of nodes without points

    void build(glm::vec3* begin, glm::vec3* end, int node, int firstRegion, int regions, const RegionBox& box) {
        if (regions == 1) {
            nodes[std::size_t(node)] = KdNode{.region = firstRegion};
            return;
        }
        const std::size_t m = std::size_t(end - begin);
        const int lowerRegions = regions / 2;
        int axis = 0;
        float split = 0.0f;
        if (m == 0) {
            const glm::vec3 lo = glm::clamp(box.lo, data.lo, data.hi), hi = glm::clamp(box.hi, data.lo, data.hi);
            axis = longestAxis(hi - lo);
            split = std::clamp(lo[axis] + 0.5f * (hi[axis] - lo[axis]), box.lo[axis], box.hi[axis]);
        } else {
            const Bounds b = boundsOf(begin, m);
            axis = longestAxis(b.extent());
            auto less = [axis](const glm::vec3& p, const glm::vec3& q) { return p[axis] < q[axis]; };
            // The weighted quantile floor(n/2) / n with unit weights: the lower child's count.
            const auto k = std::size_t(std::llround(double(m) * lowerRegions / regions));
            if (k == 0) {
                split = b.lo[axis];
            } else if (k == m) {
                split = std::nextafter(b.hi[axis], kInfinity);
            } else {
                std::nth_element(begin, begin + k, end, less);
                const float above = begin[k][axis];
                const float below = (*std::max_element(begin, begin + k, less))[axis];
                // Halfway, unless the two are adjacent floats (then the halfway point rounds onto
                // `below`, which would send it up): the plane then lies on `above`.
                split = below + 0.5f * (above - below);
                if (!(split > below)) split = above;
            }
        }
        TC_CHECK(std::isfinite(split) && split >= box.lo[axis] && split <= box.hi[axis]);
        glm::vec3* middle = std::partition(begin, end, [&](const glm::vec3& p) { return p[axis] < split; });

        const int lowerNode = node + 1, upperNode = node + 2 * lowerRegions;
        nodes[std::size_t(node)] = KdNode{.axis = axis, .split = split, .lower = lowerNode, .upper = upperNode};
        RegionBox lowerBox = box, upperBox = box;
        lowerBox.hi[axis] = split;
        upperBox.lo[axis] = split;
        auto lower = [&] { build(begin, middle, lowerNode, firstRegion, lowerRegions, lowerBox); };
        auto upper = [&] {
            build(middle, end, upperNode, firstRegion + lowerRegions, regions - lowerRegions, upperBox);
        };
        if (m >= kParallelBuildPoints) {
            tbb::parallel_invoke(lower, upper);
        } else {
            lower();
            upper();
        }
    }
};

void overlapping(const std::vector<KdNode>& nodes, int node, const Bounds& box, std::vector<int>& out) {
    const KdNode& n = nodes[std::size_t(node)];
    if (n.leaf()) {
        out.push_back(n.region);
        return;
    }
    if (box.lo[n.axis] < n.split) overlapping(nodes, n.lower, box, out);
    if (box.hi[n.axis] >= n.split) overlapping(nodes, n.upper, box, out);
}

// Front to back: at every split, the child `upperFirst` says first.
template <class UpperFirst>
std::vector<int> frontToBack(const std::vector<KdNode>& nodes, std::size_t regionCount, UpperFirst upperFirst) {
    std::vector<int> order;
    order.reserve(regionCount);
    std::vector<int> stack{0};
    while (!stack.empty()) {
        const KdNode& n = nodes[std::size_t(stack.back())];
        stack.pop_back();
        if (n.leaf()) {
            order.push_back(n.region);
            continue;
        }
        const bool up = upperFirst(n);
        stack.push_back(up ? n.lower : n.upper);  // second
        stack.push_back(up ? n.upper : n.lower);  // first
    }
    return order;
}

// The slack of assignSegments / assignParticles around a sphere (centre x, radius r).
float assignmentSlack(const glm::vec3& x, float r) {
    const glm::vec3 a = glm::abs(x);
    return 1e-2f * r + 1e-5f * (std::max({a.x, a.y, a.z}) + r);
}

// Per region, the ascending items of [0, units) that `fill(unitBegin, unitEnd, lists)` puts there.
// Units (particles, or polylines whose segments are consecutive) are assigned in fixed chunks in
// parallel, each into its own lists, which are then concatenated in chunk order: the lists come
// out ascending, the same on any number of threads, without a sort.
template <class Fill>
RegionItems assignChunked(const KdDecomposition& tree, std::size_t units, std::size_t chunk, Fill fill) {
    const std::size_t regionCount = std::size_t(tree.regionCount());
    // At most kMaxChunks chunks: each holds one (mostly empty) list per region.
    constexpr std::size_t kMaxChunks = 256;
    chunk = std::max(chunk, (units + kMaxChunks - 1) / kMaxChunks);
    const std::size_t chunks = (units + chunk - 1) / chunk;
    std::vector<RegionItems> perChunk(chunks, RegionItems(regionCount));
    tbb::parallel_for(std::size_t(0), chunks,
                      [&](std::size_t c) { fill(c * chunk, std::min(units, (c + 1) * chunk), perChunk[c]); });
    RegionItems result(regionCount);
    tbb::parallel_for(std::size_t(0), regionCount, [&](std::size_t r) {
        std::size_t total = 0;
        for (const RegionItems& items : perChunk) total += items[r].size();
        result[r].reserve(total);
        for (RegionItems& items : perChunk) {
            result[r].insert(result[r].end(), items[r].begin(), items[r].end());
            std::vector<std::uint32_t>().swap(items[r]);
        }
    });
    return result;
}

// For each segment of polylines [firstPolyline, endPolyline): f(segment, v), v its first vertex.
template <class F>
void forEachSegment(const LineSet& lines, std::size_t firstPolyline, std::size_t endPolyline, F f) {
    for (std::size_t p = firstPolyline; p < endPolyline; ++p)
        for (std::uint32_t v = lines.offsets[p]; v + 1 < lines.offsets[p + 1]; ++v) f(std::size_t(v) - p, v);
}

template <class Radius>
RegionItems assignSegmentsWith(const KdDecomposition& tree, const LineSet& lines, Radius radius) {
    // Chunks of polylines sized for about kVectorChunk segments each.
    const std::size_t polylines = lines.polylineCount();
    const std::size_t meanSegments =
        std::max<std::size_t>(1, lines.segmentCount() / std::max<std::size_t>(1, polylines));
    const std::size_t chunk = std::max<std::size_t>(1, std::size_t(kVectorChunk) / meanSegments);
    return assignChunked(tree, polylines, chunk, [&](std::size_t begin, std::size_t end, RegionItems& items) {
        std::vector<int> regions;
        forEachSegment(lines, begin, end, [&](std::size_t s, std::uint32_t v) {
            const glm::vec3 a = lines.positions[v], b = lines.positions[v + 1];
            const float ra = radius(v), rb = radius(v + 1);
            const float slack = std::max(assignmentSlack(a, ra), assignmentSlack(b, rb));
            Bounds box;
            box.extend(a, ra + slack);
            box.extend(b, rb + slack);
            tree.regionsOverlapping(box, regions);
            for (int r : regions) items[std::size_t(r)].push_back(std::uint32_t(s));
        });
    });
}

template <class Radius>
RegionItems assignParticlesWith(const KdDecomposition& tree, const ParticleSet& particles, Radius radius) {
    return assignChunked(tree, particles.size(), std::size_t(kVectorChunk),
                         [&](std::size_t begin, std::size_t end, RegionItems& items) {
                             std::vector<int> regions;
                             for (std::size_t i = begin; i < end; ++i) {
                                 const glm::vec3 c = particles.positions[i];
                                 const float r = radius(i);
                                 Bounds box;
                                 box.extend(c, r + assignmentSlack(c, r));
                                 tree.regionsOverlapping(box, regions);
                                 for (int region : regions) items[std::size_t(region)].push_back(std::uint32_t(i));
                             }
                         });
}

}  // namespace

// --- the tree ------------------------------------------------------------------------------

KdDecomposition::KdDecomposition() : KdDecomposition(std::vector<KdNode>{KdNode{.region = 0}}) {}

KdDecomposition::KdDecomposition(std::vector<KdNode> nodes) : m_nodes(std::move(nodes)) {
    // Boxes by descending from the root with all of space.
    std::size_t leaves = 0;
    for (const KdNode& n : m_nodes) leaves += n.leaf();
    m_boxes.resize(leaves);
    std::vector<std::pair<int, RegionBox>> stack{{0, RegionBox{}}};
    while (!stack.empty()) {
        auto [i, box] = stack.back();
        stack.pop_back();
        const KdNode& n = m_nodes[std::size_t(i)];
        if (n.leaf()) {
            m_boxes[std::size_t(n.region)] = box;
            continue;
        }
        RegionBox lower = box, upper = box;
        lower.hi[n.axis] = n.split;
        upper.lo[n.axis] = n.split;
        stack.push_back({n.lower, lower});
        stack.push_back({n.upper, upper});
    }
}

KdDecomposition KdDecomposition::build(std::vector<glm::vec3> points, int regionCount) {
    TC_CHECK_OP(regionCount, >=, 1);
    std::vector<KdNode> nodes(2 * std::size_t(regionCount) - 1);
    TreeBuilder builder{nodes, boundsOf(points.data(), points.size())};
    if (builder.data.empty()) builder.data = Bounds{glm::vec3(0.0f), glm::vec3(0.0f)};
    builder.build(points.data(), points.data() + points.size(), 0, 0, regionCount, RegionBox{});
    return KdDecomposition(std::move(nodes));
}

KdDecomposition KdDecomposition::fromNodes(std::vector<KdNode> nodes, const std::string& where) {
    auto fail = [&](std::size_t i, const std::string& message) {
        throw InputError(where + ": nodes[" + std::to_string(i) + "]: " + message);
    };
    if (nodes.empty()) throw InputError(where + ": nodes: the tree has no nodes");
    std::size_t leaves = 0;
    for (const KdNode& n : nodes) leaves += n.leaf();
    std::vector<bool> reached(nodes.size(), false), numbered(leaves, false);
    std::vector<std::pair<std::size_t, RegionBox>> stack{{0, RegionBox{}}};
    reached[0] = true;
    while (!stack.empty()) {
        auto [i, box] = stack.back();
        stack.pop_back();
        const KdNode& n = nodes[i];
        if (n.leaf()) {
            if (n.region < 0 || std::size_t(n.region) >= leaves)
                fail(i, "region " + std::to_string(n.region) + " is not in 0.." + std::to_string(leaves - 1) +
                            " (the tree has " + std::to_string(leaves) + " leaves)");
            if (numbered[std::size_t(n.region)]) fail(i, "region " + std::to_string(n.region) + " appears twice");
            numbered[std::size_t(n.region)] = true;
            continue;
        }
        if (n.axis > 2) fail(i, "axis " + std::to_string(n.axis) + " is not 0, 1 or 2");
        if (!std::isfinite(n.split) || n.split < box.lo[n.axis] || n.split > box.hi[n.axis])
            fail(i, "split " + std::to_string(n.split) + " lies outside the node's box [" +
                        std::to_string(box.lo[n.axis]) + ", " + std::to_string(box.hi[n.axis]) + "] along " +
                        kAxisNames[n.axis]);
        for (int child : {n.lower, n.upper}) {
            if (child < 0 || std::size_t(child) >= nodes.size())
                fail(i, "child " + std::to_string(child) + " is not a node index");
            if (reached[std::size_t(child)]) fail(i, "child " + std::to_string(child) + " is reached twice");
            reached[std::size_t(child)] = true;
        }
        RegionBox lower = box, upper = box;
        lower.hi[n.axis] = n.split;
        upper.lo[n.axis] = n.split;
        stack.push_back({std::size_t(n.lower), lower});
        stack.push_back({std::size_t(n.upper), upper});
    }
    for (std::size_t i = 0; i < nodes.size(); ++i)
        if (!reached[i]) fail(i, "not reachable from the root");
    return KdDecomposition(std::move(nodes));
}

nlohmann::json KdDecomposition::toJson() const {
    nlohmann::json nodes = nlohmann::json::array();
    for (const KdNode& n : m_nodes) {
        if (n.leaf())
            nodes.push_back({{"region", n.region}});
        else
            nodes.push_back(
                {{"axis", kAxisNames[n.axis]}, {"split", double(n.split)}, {"lower", n.lower}, {"upper", n.upper}});
    }
    return {{"regions", regionCount()}, {"nodes", std::move(nodes)}};
}

KdDecomposition KdDecomposition::fromJson(const nlohmann::json& tree, const std::string& where) {
    SpecReader r(tree, where, "tree");
    const int regions = r.getInt("regions", -1, 1, std::numeric_limits<int>::max());
    if (regions < 0) r.fail("regions", "missing required key");
    const nlohmann::json& list = r.raw("nodes");
    if (!list.is_array() || list.size() != 2 * std::size_t(regions) - 1)
        r.fail("nodes", "expected an array of " + std::to_string(2 * std::size_t(regions) - 1) + " nodes (" +
                            std::to_string(regions) + " regions), got " +
                            (list.is_array() ? std::to_string(list.size()) + " entries" : describeJson(list)));
    r.finish();
    std::vector<KdNode> nodes(list.size());
    constexpr int kMaxIndex = std::numeric_limits<int>::max();
    for (std::size_t i = 0; i < list.size(); ++i) {
        SpecReader n(list[i], where, "tree.nodes[" + std::to_string(i) + "]");
        if (n.has("region")) {
            nodes[i].region = n.getInt("region", -1, 0, regions - 1);
        } else {
            const std::string axis = n.getEnum("axis", "", {"x", "y", "z"});
            if (axis.empty())
                n.fail("axis", "missing required key (a split node has axis, split, lower, upper; a leaf has region)");
            nodes[i].axis = axis[0] - 'x';
            if (!n.has("split")) n.fail("split", "missing required key");
            nodes[i].split =
                n.getFloat("split", 0.0f, -std::numeric_limits<float>::max(), std::numeric_limits<float>::max());
            if (!n.has("lower") || !n.has("upper")) n.fail(n.has("lower") ? "upper" : "lower", "missing required key");
            nodes[i].lower = n.getInt("lower", -1, 1, kMaxIndex);
            nodes[i].upper = n.getInt("upper", -1, 1, kMaxIndex);
        }
        n.finish();
    }
    return fromNodes(std::move(nodes), where + ": tree");
}

int KdDecomposition::regionOf(const glm::vec3& p) const {
    const KdNode* n = &m_nodes[0];
    while (!n->leaf()) n = &m_nodes[std::size_t(p[n->axis] < n->split ? n->lower : n->upper)];
    return n->region;
}

void KdDecomposition::regionsOverlapping(const Bounds& box, std::vector<int>& out) const {
    out.clear();
    overlapping(m_nodes, 0, box, out);
    std::sort(out.begin(), out.end());  // a built tree numbers regions depth first: already sorted
}

std::vector<int> KdDecomposition::viewOrderFromPosition(const glm::vec3& eye) const {
    return frontToBack(m_nodes, m_boxes.size(), [&](const KdNode& n) { return eye[n.axis] >= n.split; });
}

std::vector<int> KdDecomposition::viewOrderInDirection(const glm::vec3& direction) const {
    return frontToBack(m_nodes, m_boxes.size(), [&](const KdNode& n) { return direction[n.axis] < 0.0f; });
}

std::vector<int> KdDecomposition::viewOrder(const Camera& camera) const {
    return camera.projection == Projection::Orthographic ? viewOrderInDirection(camera.forward())
                                                         : viewOrderFromPosition(camera.eye);
}

// --- assignment ----------------------------------------------------------------------------

std::vector<glm::vec3> segmentMidpoints(const LineSet& lines) {
    std::vector<glm::vec3> midpoints(lines.segmentCount());
    forChunks(std::int64_t(lines.polylineCount()), [&](std::int64_t begin, std::int64_t end) {
        forEachSegment(lines, std::size_t(begin), std::size_t(end), [&](std::size_t s, std::uint32_t v) {
            midpoints[s] = segmentMidpoint(lines.positions[v], lines.positions[v + 1]);
        });
    });
    return midpoints;
}

RegionItems assignSegments(const KdDecomposition& tree, const LineSet& lines, float radius) {
    TC_CHECK(radius >= 0.0f);
    return assignSegmentsWith(tree, lines, [radius](std::uint32_t) { return radius; });
}

RegionItems assignSegments(const KdDecomposition& tree, const LineSet& lines, std::span<const float> vertexRadii) {
    TC_CHECK_OP(vertexRadii.size(), ==, lines.vertexCount());
    return assignSegmentsWith(tree, lines, [vertexRadii](std::uint32_t v) { return vertexRadii[v]; });
}

RegionItems assignParticles(const KdDecomposition& tree, const ParticleSet& particles, float radius) {
    TC_CHECK(radius >= 0.0f);
    return assignParticlesWith(tree, particles, [radius](std::size_t) { return radius; });
}

RegionItems assignParticles(const KdDecomposition& tree, const ParticleSet& particles, std::span<const float> radii) {
    TC_CHECK_OP(radii.size(), ==, particles.size());
    return assignParticlesWith(tree, particles, [radii](std::size_t i) { return radii[i]; });
}

std::vector<std::uint32_t> ownedSegments(const KdDecomposition& tree, int region, const LineSet& lines) {
    std::vector<std::uint32_t> owned;
    forEachSegment(lines, 0, lines.polylineCount(), [&](std::size_t s, std::uint32_t v) {
        if (tree.regionOf(segmentMidpoint(lines.positions[v], lines.positions[v + 1])) == region)
            owned.push_back(std::uint32_t(s));
    });
    return owned;
}

std::vector<std::uint32_t> ownedParticles(const KdDecomposition& tree, int region, const ParticleSet& particles) {
    std::vector<std::uint32_t> owned;
    for (std::size_t i = 0; i < particles.size(); ++i)
        if (tree.regionOf(particles.positions[i]) == region) owned.push_back(std::uint32_t(i));
    return owned;
}

// --- extraction ----------------------------------------------------------------------------

RegionLines extractRegionLines(const LineSet& lines, std::span<const std::uint32_t> segments) {
    TC_CHECK(std::is_sorted(segments.begin(), segments.end()));
    TC_CHECK(segments.empty() || segments.back() < lines.segmentCount());
    RegionLines out;
    out.lines.velocity = lines.velocity;
    for (const Attribute& a : lines.attributes) out.lines.attributes.push_back({a.name, {}, a.min, a.max});
    auto appendVertices = [&](std::uint32_t first, std::uint32_t last) {  // inclusive
        out.lines.positions.insert(out.lines.positions.end(), lines.positions.begin() + first,
                                   lines.positions.begin() + last + 1);
        for (std::size_t a = 0; a < lines.attributes.size(); ++a)
            out.lines.attributes[a].values.insert(out.lines.attributes[a].values.end(),
                                                  lines.attributes[a].values.begin() + first,
                                                  lines.attributes[a].values.begin() + last + 1);
        out.lines.offsets.push_back(std::uint32_t(out.lines.positions.size()));
    };

    std::size_t p = 0;  // the polyline of segments[i]; segments ascend, so it only moves forward
    for (std::size_t i = 0; i < segments.size();) {
        // Segment s of polyline p starts at vertex s + p.
        while (std::size_t(lines.offsets[p + 1]) - (p + 1) <= segments[i]) ++p;
        const std::uint32_t begin = lines.offsets[p], end = lines.offsets[p + 1];
        const std::uint32_t firstSegmentVertex = std::uint32_t(segments[i] + p);
        std::uint32_t lastSegmentVertex = firstSegmentVertex;
        // Extend the run while the next assigned segment is of this polyline and at most two
        // segments after the run's last (a gap of <= 2 costs no more than two runs' neighbours).
        for (++i; i < segments.size(); ++i) {
            const std::size_t v = segments[i] + p;
            if (v + 1 >= end || v > std::size_t(lastSegmentVertex) + 3) break;
            lastSegmentVertex = std::uint32_t(v);
        }
        // One neighbour segment each way where the polyline continues (the header says why).
        const std::uint32_t first = firstSegmentVertex > begin ? firstSegmentVertex - 1 : firstSegmentVertex;
        const std::uint32_t last = std::min(lastSegmentVertex + 2, end - 1);  // the run's last vertex
        appendVertices(first, last);
        out.origins.push_back({p, first});
    }
    out.lines.updateBounds();
    return out;
}

ParticleSet extractParticles(const ParticleSet& particles, std::span<const std::uint32_t> indices) {
    ParticleSet out;
    out.radiiFrom = particles.radiiFrom;
    out.colorsFrom = particles.colorsFrom;
    out.elementRadii = particles.elementRadii;
    out.positions.reserve(indices.size());
    for (std::uint32_t i : indices) out.positions.push_back(particles.positions[i]);
    if (!particles.radii.empty())
        for (std::uint32_t i : indices) out.radii.push_back(particles.radii[i]);
    if (!particles.colors.empty())
        for (std::uint32_t i : indices) out.colors.push_back(particles.colors[i]);
    for (const Attribute& a : particles.attributes) {
        Attribute& b = out.attributes.emplace_back(Attribute{a.name, {}, a.min, a.max});
        b.values.reserve(indices.size());
        for (std::uint32_t i : indices) b.values.push_back(a.values[i]);
    }
    for (const glm::vec3& p : out.positions) out.bounds.extend(p);
    return out;
}

std::vector<glm::vec3> transportedTangents(const LineSet& lines) {
    std::vector<glm::vec3> out(lines.segmentCount());
    std::size_t s = 0;
    for (std::size_t p = 0; p < lines.polylineCount(); ++p) {
        glm::vec3 carried(0.0f);  // nothing carried into a polyline's first segment
        for (std::uint32_t v = lines.offsets[p]; v + 1 < lines.offsets[p + 1]; ++v, ++s) {
            const glm::vec3 axis = segmentAxis(lines.positions[v], lines.positions[v + 1]);
            glm::vec3 t, b;
            tangentFrame(axis, t, b);
            carried = out[s] = transportTangent(carried, axis, t);
        }
    }
    return out;
}

std::vector<glm::vec3> incomingTangents(const LineSet& lines, std::span<const glm::vec3> transported,
                                        std::span<const RunOrigin> origins) {
    TC_CHECK_OP(transported.size(), ==, lines.segmentCount());
    std::vector<glm::vec3> out(origins.size(), glm::vec3(0.0f));
    for (std::size_t q = 0; q < origins.size(); ++q) {
        const RunOrigin& o = origins[q];
        TC_CHECK(o.polyline < lines.polylineCount());
        // Segment S of polyline P starts at vertex S + P: the one ending at the run's first vertex
        // is firstVertex - 1 - P.
        if (o.firstVertex > lines.offsets[o.polyline]) out[q] = transported[o.firstVertex - 1 - o.polyline];
    }
    return out;
}

}  // namespace tc
