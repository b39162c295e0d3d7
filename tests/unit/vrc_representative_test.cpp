// Representative lines of the VRC LoD (core/vrc_representative.h): the average of parallel pieces
// (with the flip test), lines on a straight input and their connection across faces, and the
// conservation of the Eq. 1 weights over the levels.
#include "core/vrc_representative.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/vrc_model.h"
#include "test_scenes.h"

namespace tc {
namespace {

struct Vertex {
    glm::vec3 p;
    float r;
    float alpha;
};

// One colour for every vertex; the alphas as given.
StyledLines makeLines(const std::vector<std::vector<Vertex>>& polylines) {
    std::vector<test::TestPolyline> coloured;
    for (const auto& pl : polylines) {
        coloured.emplace_back();
        for (const Vertex& v : pl) coloured.back().push_back({v.p, v.r, glm::vec4(0.5f, 0.6f, 0.7f, v.alpha)});
    }
    return test::makeStyledLines(coloured);
}

double pointLineDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 u = glm::normalize(b - a);
    const glm::dvec3 d = p - a;
    return glm::length(d - glm::dot(d, u) * u);
}

TEST(VrcRepresentative, representative_of_parallel_pieces_is_their_average_also_when_one_is_reversed) {
    // A diagonal fixes the bounds (and the grid); two x-parallel lines 0.1 voxel above and below
    // the centre of a voxel row, the second drawn in the opposite direction, with radii 0.004 and
    // 0.008: in each voxel holding only those two, the representative runs along the row's centre
    // line from x face to x face with radius 0.006.
    const Vertex d0{glm::vec3(0.0f), 0.004f, 1.0f}, d1{glm::vec3(1.0f), 0.004f, 1.0f};
    VrcBuildOptions o;
    o.resolution = 16;
    for (int q : {0, 16}) {
        o.quantization = q;
        const VrcModel grid = emptyVrcModel(makeLines({{d0, d1}}), o);
        const float h = grid.voxelSize;
        const float y0 = grid.origin.y + (std::floor((0.3f - grid.origin.y) / h) + 0.5f) * h;
        const float z0 = grid.origin.z + (std::floor((0.7f - grid.origin.z) / h) + 0.5f) * h;
        const float dy = 0.1f * h, dz = 0.05f * h;
        const StyledLines lines = makeLines(
            {{d0, d1},
             {{glm::vec3(0.05f, y0 - dy, z0 + dz), 0.004f, 1.0f}, {glm::vec3(0.95f, y0 - dy, z0 + dz), 0.004f, 1.0f}},
             {{glm::vec3(0.95f, y0 + dy, z0 - dz), 0.008f, 1.0f}, {glm::vec3(0.05f, y0 + dy, z0 - dz), 0.008f, 1.0f}}});
        const VrcModel m = buildVrcModel(lines, o);
        ASSERT_EQ(m.voxelSize, h);
        const auto levels = buildRepresentativeLines(m, 0);
        ASSERT_EQ(levels.size(), 1u);
        const double bound = q > 0 ? vrcFaceQuantizationBound(m) + 1e-6 : 1e-5;
        int checked = 0;
        for (std::size_t v = 0; v < m.voxelCount(); ++v) {
            const VrcVoxel& hd = m.voxels[v];
            const std::uint32_t count = hd.count & kCountMask;
            bool only = count == 2;
            for (std::uint32_t k = 0; k < count; ++k) {
                const VrcPiece p = m.piece(hd.offset + k);
                only = only && p.line != 0 && !p.vertexA && !p.vertexB;  // both cross the voxel
            }
            if (!only) continue;
            const glm::ivec3 c = m.coords(v);
            const VrcRepresentativeLine& r = levels[0].lines[v];
            const double xLow = m.origin.x + double(c.x) * h, xHigh = xLow + h;
            // The flip test keeps the reversed line from cancelling: the representative spans the
            // voxel (in the heavier, second line's direction), ends on the x faces.
            const glm::dvec3 a(r.a), b(r.b);
            EXPECT_NEAR(std::min(a.x, b.x), xLow, 1e-5);
            EXPECT_NEAR(std::max(a.x, b.x), xHigh, 1e-5);
            for (const glm::dvec3& e : {a, b}) {
                EXPECT_LE(std::hypot(e.y - y0, e.z - z0), bound) << "q=" << q;
            }
            EXPECT_NEAR(r.radius, 0.006f, 1e-6f);
            EXPECT_NEAR(r.weight, 2.0f, 1e-4f);  // two pieces of one voxel length, opacity 1
            ++checked;
        }
        EXPECT_GE(checked, 8) << "q=" << q;
    }
}

TEST(VrcRepresentative, straight_line_representatives_lie_on_it_and_form_a_connected_chain_at_every_level) {
    const glm::vec3 p0(0.1f, 0.2f, 0.15f), p1(0.9f, 0.75f, 0.6f);
    const StyledLines lines =
        makeLines({{{p0, 0.003f, 0.5f}, {glm::mix(p0, p1, 0.37f), 0.003f, 0.5f}, {p1, 0.003f, 0.5f}}});
    VrcBuildOptions o;
    o.resolution = 32;
    o.quantization = 0;
    const VrcModel m = buildVrcModel(lines, o);
    const auto levels = buildRepresentativeLines(m, 4);
    ASSERT_EQ(levels.size(), 5u);
    for (const VrcRepresentativeLevel& level : levels) {
        std::size_t valid = 0, faceEnds = 0, connected = 0;
        for (int z = 0; z < level.size.z; ++z)
            for (int y = 0; y < level.size.y; ++y)
                for (int x = 0; x < level.size.x; ++x) {
                    const glm::ivec3 v(x, y, z);
                    const VrcRepresentativeLine& r = level.lines[level.index(v)];
                    if (r.weight <= 0.0f) continue;
                    ++valid;
                    EXPECT_LT(pointLineDistance(glm::dvec3(r.a), glm::dvec3(p0), glm::dvec3(p1)), 1e-5);
                    EXPECT_LT(pointLineDistance(glm::dvec3(r.b), glm::dvec3(p0), glm::dvec3(p1)), 1e-5)
                        << "voxel " << x << "," << y << "," << z << " a (" << r.a.x << "," << r.a.y << "," << r.a.z
                        << ") face " << r.faceA << " b (" << r.b.x << "," << r.b.y << "," << r.b.z << ") face "
                        << r.faceB << " level voxel " << level.voxelSize;
                    // Each end on a face shared with another valid voxel meets that voxel's line.
                    for (auto [end, face] : {std::pair{r.a, r.faceA}, std::pair{r.b, r.faceB}}) {
                        if (face == kInteriorFace) continue;  // a point line (slivers)
                        glm::ivec3 n = v;
                        n[int(face / 2)] += (face & 1u) ? 1 : -1;
                        if (glm::any(glm::lessThan(n, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(n, level.size)))
                            continue;
                        const VrcRepresentativeLine& o2 = level.lines[level.index(n)];
                        if (o2.weight <= 0.0f || o2.faceA == kInteriorFace) continue;
                        ++faceEnds;
                        connected += o2.a == end || o2.b == end;
                    }
                }
        EXPECT_GE(valid, level.level < 4 ? 2u : 1u) << "level " << level.level;
        EXPECT_EQ(connected, faceEnds) << "level " << level.level;
        if (level.level < 3) {
            EXPECT_GT(faceEnds, 0u) << "level " << level.level;
        }
    }
}

TEST(VrcRepresentative, weights_are_conserved_over_the_levels_and_copies_are_not_counted) {
    std::mt19937 rng(21);
    auto uniform = [&] { return float(rng()) / 4294967296.0f; };
    std::vector<std::vector<Vertex>> curves;
    for (int c = 0; c < 30; ++c) {
        std::vector<Vertex> pl;
        glm::vec3 p(uniform(), uniform(), uniform());
        glm::vec3 dir = glm::normalize(glm::vec3(uniform() - 0.5f, uniform() - 0.5f, uniform() - 0.5f) + 1e-3f);
        for (int i = 0; i < 40; ++i) {
            pl.push_back({p, 0.004f, 0.2f + 0.8f * uniform()});
            dir = glm::normalize(dir + 0.7f * glm::vec3(uniform() - 0.5f, uniform() - 0.5f, uniform() - 0.5f));
            p += 0.03f * dir;
        }
        curves.push_back(pl);
    }
    const StyledLines lines = makeLines(curves);
    VrcBuildOptions o;
    o.resolution = 40;  // odd sizes on the way up: 40 -> 20 -> 10 -> 5 -> 3 -> 2 -> 1
    o.quantization = 16;
    const VrcModel m = buildVrcModel(lines, o);
    o.dilate = true;
    const VrcModel dilated = buildVrcModel(lines, o);
    double expected = 0;
    for (std::size_t i = 0; i < m.pieceCount(); ++i) {
        const VrcPiece p = m.piece(i);
        expected += double(glm::distance(p.a, p.b)) / m.voxelSize * p.color.w;
    }
    const auto levels = buildRepresentativeLines(m, 10);
    const auto levelsDilated = buildRepresentativeLines(dilated, 10);
    ASSERT_EQ(levels.size(), 7u);
    ASSERT_EQ(levelsDilated.size(), levels.size());
    std::size_t connected = 0, faceEnds = 0;
    for (std::size_t l = 0; l < levels.size(); ++l) {
        double total = 0, totalDilated = 0;
        for (const VrcRepresentativeLine& r : levels[l].lines) total += r.weight;
        for (const VrcRepresentativeLine& r : levelsDilated[l].lines) totalDilated += r.weight;
        EXPECT_NEAR(total, expected, 1e-5 * expected) << "level " << l;
        EXPECT_NEAR(totalDilated, expected, 1e-5 * expected) << "level " << l;
        // Connection: ends on a shared face within half a voxel of the neighbour's end coincide.
        const VrcRepresentativeLevel& level = levels[l];
        for (int z = 0; z < level.size.z; ++z)
            for (int y = 0; y < level.size.y; ++y)
                for (int x = 0; x < level.size.x; ++x) {
                    const glm::ivec3 v(x, y, z);
                    const VrcRepresentativeLine& r = level.lines[level.index(v)];
                    if (r.weight <= 0.0f) continue;
                    for (auto [end, face] : {std::pair{r.a, r.faceA}, std::pair{r.b, r.faceB}}) {
                        if (face == kInteriorFace) continue;  // a point line (slivers)
                        glm::ivec3 n = v;
                        n[int(face / 2)] += (face & 1u) ? 1 : -1;
                        if (glm::any(glm::lessThan(n, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(n, level.size)))
                            continue;
                        const VrcRepresentativeLine& o2 = level.lines[level.index(n)];
                        if (o2.weight <= 0.0f || o2.faceA == kInteriorFace) continue;
                        const std::uint32_t opposite = face ^ 1u;
                        const glm::vec3* partner = o2.faceA == opposite   ? &o2.a
                                                   : o2.faceB == opposite ? &o2.b
                                                                          : nullptr;
                        if (!partner || glm::distance(*partner, end) > 0.5f * level.voxelSize) continue;
                        ++faceEnds;
                        connected += *partner == end;
                    }
                }
    }
    EXPECT_GT(faceEnds, 50u);
    EXPECT_EQ(connected, faceEnds);
}

}  // namespace
}  // namespace tc
