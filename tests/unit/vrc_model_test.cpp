// The VRC voxel model (core/vrc_model.h): clipping at voxel faces, quantization error bounds,
// the piecewise approximation's distance to the input (Hausdorff), the header/array layout,
// connectivity across faces, determinism, the Eq. 1 density pyramid's totals and the ray caster's
// LoD volume (extinction per voxel, its totals per level).
#include "core/vrc_model.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "test_scenes.h"

namespace tc {
namespace {

using Vertex = test::TestVertex;
constexpr auto makeLines = test::makeStyledLines;

// Random smooth-ish curves: random walks with bounded turning, random radius, colour and alpha.
// Uses std::mt19937's raw output only (distributions are implementation-defined).
std::vector<std::vector<Vertex>> randomCurves(std::uint32_t seed, int count, int points, float step) {
    std::mt19937 rng(seed);
    auto uniform = [&] { return float(rng()) / 4294967296.0f; };
    std::vector<std::vector<Vertex>> curves;
    for (int c = 0; c < count; ++c) {
        std::vector<Vertex> pl;
        glm::vec3 p(uniform() * 2 - 1, uniform() * 2 - 1, uniform() * 2 - 1);
        glm::vec3 dir = glm::normalize(glm::vec3(uniform() - 0.5f, uniform() - 0.5f, uniform() - 0.5f) + 1e-3f);
        for (int i = 0; i < points; ++i) {
            pl.push_back(
                {p, 0.005f + 0.02f * uniform(), glm::vec4(uniform(), uniform(), uniform(), 0.2f + 0.8f * uniform())});
            dir = glm::normalize(dir + 0.8f * glm::vec3(uniform() - 0.5f, uniform() - 0.5f, uniform() - 0.5f));
            p += step * (0.3f + uniform()) * dir;
        }
        curves.push_back(pl);
    }
    return curves;
}

double pointSegmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 ab = b - a;
    const double l2 = glm::dot(ab, ab);
    const double t = l2 > 0 ? std::clamp(glm::dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

// Distance from p to polyline `pl`.
double distanceToPolyline(const glm::dvec3& p, const std::vector<Vertex>& pl) {
    double d = 1e30;
    for (std::size_t i = 0; i + 1 < pl.size(); ++i)
        d = std::min(d, pointSegmentDistance(p, glm::dvec3(pl[i].position), glm::dvec3(pl[i + 1].position)));
    return d;
}

VrcModel build(const StyledLines& lines, int resolution, int q) {
    VrcBuildOptions o;
    o.resolution = resolution;
    o.quantization = q;
    return buildVrcModel(lines, o);
}

TEST(VrcModel, straight_axis_aligned_line_gives_one_piece_per_voxel_with_ends_on_faces) {
    // A line along x through voxel centres: 2 vertex pieces + one piece per interior voxel.
    const StyledLines lines =
        makeLines({{{glm::vec3(0, 0, 0), 0.01f, glm::vec4(1)}, {glm::vec3(1, 0, 0), 0.01f, glm::vec4(1)}}});
    const VrcModel m = build(lines, 11, 0);
    ASSERT_GT(m.voxelSize, 0.0f);
    const double x0 = (0.0 - m.origin.x) / m.voxelSize, x1 = (1.0 - m.origin.x) / m.voxelSize;
    const int expected = int(std::floor(x1)) - int(std::floor(x0)) + 1;
    EXPECT_EQ(int(m.pieceCount()), expected);
    double length = 0;
    for (std::size_t i = 0; i < m.pieceCount(); ++i) {
        const VrcPiece p = m.piece(i);
        length += glm::length(p.b - p.a);
        EXPECT_EQ(p.line, 0u);
        // Face ends lie on an x face of their voxel.
        const glm::ivec3 v = m.coords(m.pieceVoxel[i]);
        for (auto [end, vertex] : {std::pair{p.a, p.vertexA}, std::pair{p.b, p.vertexB}}) {
            if (vertex) continue;
            const double gx = (end.x - m.origin.x) / m.voxelSize;
            EXPECT_NEAR(std::min(std::abs(gx - v.x), std::abs(gx - v.x - 1)), 0.0, 1e-5);
        }
    }
    EXPECT_NEAR(length, 1.0, 1e-5);
}

TEST(VrcModel, quantized_end_points_lie_within_half_a_bin_diagonal_of_the_exact_face_hits) {
    const auto curves = randomCurves(7, 40, 30, 0.08f);
    const StyledLines lines = makeLines(curves);
    const VrcModel exact = build(lines, 32, 0);
    for (int q : {1, 4, 16, 32, 90}) {
        const VrcModel quant = build(lines, 32, q);
        ASSERT_EQ(quant.pieceCount(), exact.pieceCount()) << "q=" << q;
        const float faceBound = vrcFaceQuantizationBound(quant), vertexBound = vrcVertexQuantizationBound(quant);
        EXPECT_NEAR(faceBound, 0.5 * std::sqrt(2.0) * quant.voxelSize / q, 1e-7);
        double worstFace = 0, worstVertex = 0;
        for (std::size_t i = 0; i < exact.pieceCount(); ++i) {
            ASSERT_EQ(quant.pieceVoxel[i], exact.pieceVoxel[i]);
            const VrcPiece e = exact.piece(i), p = quant.piece(i);
            ASSERT_EQ(e.vertexA, p.vertexA);
            ASSERT_EQ(e.vertexB, p.vertexB);
            ASSERT_EQ(e.line, p.line);
            const double da = glm::distance(glm::dvec3(e.a), glm::dvec3(p.a));
            const double db = glm::distance(glm::dvec3(e.b), glm::dvec3(p.b));
            (e.vertexA ? worstVertex : worstFace) = std::max(e.vertexA ? worstVertex : worstFace, da);
            (e.vertexB ? worstVertex : worstFace) = std::max(e.vertexB ? worstVertex : worstFace, db);
            // Radii are unorm16 of maxRadius, colours 8 bits per channel.
            EXPECT_NEAR(p.ra, e.ra, exact.maxRadius / 65535.0 + 1e-7);
            EXPECT_NEAR(p.color.w, std::clamp(e.color.w, 0.0f, 1.0f), 0.5 / 255 + 1e-6);
        }
        // Float slack: world positions are floats of magnitude ~1 (ulp 1.2e-7).
        EXPECT_LE(worstFace, faceBound + 1e-6) << "q=" << q;
        EXPECT_LE(worstVertex, vertexBound + 1e-6) << "q=" << q;
        // The bound is tight: some end point uses most of it (the test would notice a looser code).
        EXPECT_GT(worstFace, 0.5 * faceBound) << "q=" << q;
    }
}

TEST(VrcModel, exact_face_hits_lie_on_the_input_polyline) {
    const auto curves = randomCurves(11, 20, 40, 0.06f);
    const StyledLines lines = makeLines(curves);
    const VrcModel m = build(lines, 48, 0);
    double worst = 0;
    for (std::size_t i = 0; i < m.pieceCount(); ++i) {
        const VrcPiece p = m.piece(i);
        worst = std::max({worst, distanceToPolyline(glm::dvec3(p.a), curves[p.line]),
                          distanceToPolyline(glm::dvec3(p.b), curves[p.line])});
    }
    EXPECT_LT(worst, 1e-6);
}

TEST(VrcModel, piecewise_approximation_is_within_one_voxel_diagonal_of_the_input_hausdorff) {
    const auto curves = randomCurves(3, 25, 60, 0.05f);
    const StyledLines lines = makeLines(curves);
    for (int q : {0, 8, 32}) {
        const VrcModel m = build(lines, 24, q);
        const double diagonal = std::sqrt(3.0) * m.voxelSize;
        // Samples on every piece, per polyline.
        std::vector<std::vector<std::pair<glm::dvec3, glm::dvec3>>> pieces(curves.size());
        for (std::size_t i = 0; i < m.pieceCount(); ++i) {
            const VrcPiece p = m.piece(i);
            pieces[p.line].push_back({glm::dvec3(p.a), glm::dvec3(p.b)});
        }
        double approxToInput = 0, inputToApprox = 0;
        for (std::size_t c = 0; c < curves.size(); ++c) {
            ASSERT_FALSE(pieces[c].empty());
            for (const auto& [a, b] : pieces[c])
                for (int k = 0; k <= 8; ++k)
                    approxToInput = std::max(approxToInput, distanceToPolyline(glm::mix(a, b, k / 8.0), curves[c]));
            for (std::size_t i = 0; i + 1 < curves[c].size(); ++i)
                for (int k = 0; k <= 8; ++k) {
                    const glm::dvec3 s =
                        glm::mix(glm::dvec3(curves[c][i].position), glm::dvec3(curves[c][i + 1].position), k / 8.0);
                    double d = 1e30;
                    for (const auto& [a, b] : pieces[c]) d = std::min(d, pointSegmentDistance(s, a, b));
                    inputToApprox = std::max(inputToApprox, d);
                }
        }
        EXPECT_LE(std::max(approxToInput, inputToApprox), diagonal) << "q=" << q;
        // And not trivially: the curves bend inside voxels, so the chords do deviate.
        EXPECT_GT(std::max(approxToInput, inputToApprox), 0.01 * m.voxelSize) << "q=" << q;
    }
}

TEST(VrcModel, header_partitions_the_piece_array_and_totals_are_conserved) {
    const auto curves = randomCurves(5, 30, 50, 0.07f);
    const StyledLines lines = makeLines(curves);
    const VrcModel m = build(lines, 40, 32);
    std::uint64_t next = 0, pieces = 0;
    std::size_t neighbourhoodOnly = 0;
    for (std::size_t v = 0; v < m.voxelCount(); ++v) {
        const std::uint32_t count = m.voxels[v].count & kCountMask;
        if (count == 0) {
            if (m.voxels[v].count & kNeighbourhoodBit) ++neighbourhoodOnly;
            continue;
        }
        EXPECT_TRUE(m.voxels[v].count & kNeighbourhoodBit);
        EXPECT_EQ(m.voxels[v].offset, next);
        for (std::uint32_t k = 0; k < count; ++k) EXPECT_EQ(m.pieceVoxel[m.voxels[v].offset + k], v);
        next += count;
        pieces += count;
    }
    EXPECT_EQ(pieces, m.pieceCount());
    EXPECT_GT(neighbourhoodOnly, 0u);
    EXPECT_EQ(m.bytesPerPiece(), 16u);
    EXPECT_EQ(m.bytes(), m.voxelCount() * 8 + m.pieceCount() * 16);

    // Eq. 1: level 0 holds sum(length x mean opacity) in voxel lengths = the analytic total.
    double expected = 0;
    for (const auto& c : curves)
        for (std::size_t i = 0; i + 1 < c.size(); ++i)
            expected += glm::distance(glm::dvec3(c[i].position), glm::dvec3(c[i + 1].position)) * 0.5 *
                        (c[i].color.w + c[i + 1].color.w);
    expected /= m.voxelSize;
    ASSERT_GE(m.lod.size(), 2u);
    EXPECT_NEAR(m.lod[0].total(), expected, 1e-5 * expected);
    // The pyramid averages 2x2x2 with zero padding (40 -> 20 -> 10 -> 5 -> 3 -> 2 -> 1 on the
    // longest axis: odd sizes occur): total x 8^level is conserved.
    double scale = 1;
    for (const VrcDensityLevel& level : m.lod) {
        EXPECT_NEAR(level.total() * scale, expected, 1e-5 * expected) << "level size " << level.size.x;
        scale *= 8;
    }
    EXPECT_EQ(m.lod.back().size, glm::ivec3(1));
}

TEST(VrcModel, quantized_pieces_stay_connected_across_voxel_faces) {
    const auto curves = randomCurves(9, 15, 40, 0.08f);
    const StyledLines lines = makeLines(curves);
    const VrcModel m = build(lines, 20, 16);
    // Every face end has a partner: a piece of the same line in the voxel across that face with
    // a bit-identical decoded end.
    std::size_t faceEnds = 0;
    for (std::size_t i = 0; i < m.pieceCount(); ++i) {
        const VrcCompactPiece& c = m.compact[i];
        const glm::ivec3 v = m.coords(m.pieceVoxel[i]);
        for (std::uint32_t code : {c.ends & 0xFFFFu, c.ends >> 16}) {
            const std::uint32_t face = code >> kBinBits;
            if (face == kInteriorFace) continue;
            ++faceEnds;
            glm::ivec3 n = v;
            n[face / 2] += (face & 1u) ? 1 : -1;
            const glm::vec3 p = decodeEnd(m, v, code);
            const VrcVoxel& h = m.voxels[m.index(n.x, n.y, n.z)];
            bool found = false;
            for (std::uint32_t k = 0; k < (h.count & kCountMask) && !found; ++k) {
                const VrcPiece o = m.piece(h.offset + k);
                found = o.line == c.line && (o.a == p || o.b == p);
            }
            EXPECT_TRUE(found) << "piece " << i << " face " << face;
        }
    }
    EXPECT_GT(faceEnds, 100u);
}

TEST(VrcModel, copies_put_each_piece_into_every_voxel_its_tube_reaches) {
    // Points of each piece's tube (axis points pushed out by the local radius, and points on the
    // spheres at polyline end vertices) must find, in the voxel holding them, the piece itself or
    // a copy that decodes to the same world geometry; copies change neither the LoD totals nor
    // the home pieces. Within one radius of a joint with the next/previous piece (a face end) the
    // neighbouring piece covers the tube instead (core/vrc_model.h): those samples are left to
    // the GL tests on straight tubes, where the two coincide.
    const auto curves = randomCurves(17, 20, 40, 0.06f);
    const StyledLines lines = makeLines(curves);
    for (int q : {0, 16}) {
        VrcBuildOptions o;
        o.resolution = 64;
        o.quantization = q;
        const VrcModel base = buildVrcModel(lines, o);
        o.dilate = true;
        const VrcModel m = buildVrcModel(lines, o);
        ASSERT_GT(m.voxelSize, lines.maxRadius);  // copies reach one voxel out
        EXPECT_GT(m.copies, 0u);
        EXPECT_EQ(m.pieceCount(), base.pieceCount() + m.copies);
        std::size_t homes = 0;
        for (std::size_t i = 0; i < m.pieceCount(); ++i) homes += !m.piece(i).copy;
        EXPECT_EQ(homes, base.pieceCount());
        ASSERT_EQ(m.lod.size(), base.lod.size());
        EXPECT_EQ(m.lod[0].density, base.lod[0].density);
        // Header partitions the array, as without copies.
        std::uint64_t next = 0;
        for (std::size_t v = 0; v < m.voxelCount(); ++v) {
            const std::uint32_t count = m.voxels[v].count & kCountMask;
            if (count == 0) continue;
            EXPECT_EQ(m.voxels[v].offset, next);
            for (std::uint32_t k = 0; k < count; ++k) ASSERT_EQ(m.pieceVoxel[m.voxels[v].offset + k], v);
            next += count;
        }
        EXPECT_EQ(next, m.pieceCount());

        std::size_t samples = 0, outside = 0;
        for (std::size_t i = 0; i < base.pieceCount(); ++i) {
            const VrcPiece p = base.piece(i);
            const glm::vec3 axis = p.b - p.a;
            const glm::vec3 u =
                glm::normalize(glm::cross(axis + glm::vec3(1e-3f, 2e-3f, 0), glm::vec3(0.3f, 0.5f, 0.8f)));
            const glm::vec3 w = glm::normalize(glm::cross(axis + glm::vec3(1e-3f, 2e-3f, 0), u));
            std::vector<glm::vec3> points;
            const float len = glm::length(axis), rMax = std::max(p.ra, p.rb);
            const float sLo = p.vertexA ? 0.0f : std::min(rMax / len + 1e-3f, 0.5f);
            const float sHi = p.vertexB ? 1.0f : std::max(1.0f - rMax / len - 1e-3f, 0.5f);
            for (int k = 0; k <= 8; ++k)
                for (int j = 0; j < 12; ++j) {
                    const float s = sLo + (sHi - sLo) * float(k) / 8.0f, phi = 6.2831853f * float(j) / 12.0f;
                    const float r = 0.999f * (p.ra + (p.rb - p.ra) * s);
                    points.push_back(p.a + s * axis + r * (std::cos(phi) * u + std::sin(phi) * w));
                }
            for (const glm::vec3& d : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0),
                                       glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)}) {
                if (p.vertexA) points.push_back(p.a + 0.999f * p.ra * d);
                if (p.vertexB) points.push_back(p.b + 0.999f * p.rb * d);
            }
            for (const glm::vec3& x : points) {
                const glm::ivec3 v = glm::ivec3(glm::floor((x - m.origin) / m.voxelSize));
                if (glm::any(glm::lessThan(v, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(v, m.size))) {
                    ++outside;
                    continue;
                }
                ++samples;
                const VrcVoxel& h = m.voxels[m.index(v.x, v.y, v.z)];
                bool found = false;
                for (std::uint32_t k = 0; k < (h.count & kCountMask) && !found; ++k) {
                    const VrcPiece c = m.piece(h.offset + k);
                    found = c.line == p.line && c.a == p.a && c.b == p.b && c.ra == p.ra && c.rb == p.rb;
                }
                ASSERT_TRUE(found) << "q=" << q << " piece " << i << " point in voxel " << v.x << "," << v.y << ","
                                   << v.z;
            }
        }
        EXPECT_GT(samples, 50000u);
        EXPECT_EQ(outside, 0u);  // the grid keeps half a voxel of margin around the tubes
        std::printf("q=%d: %zu pieces + %zu copies (%.2fx)\n", q, base.pieceCount(), m.copies,
                    double(m.pieceCount()) / double(base.pieceCount()));
    }
}

TEST(VrcModel, build_is_identical_for_any_thread_count) {
    const auto curves = randomCurves(13, 60, 40, 0.05f);
    const StyledLines lines = makeLines(curves);
    VrcModel one;
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        one = build(lines, 32, 32);
    }
    const VrcModel many = build(lines, 32, 32);
    ASSERT_EQ(one.compact.size(), many.compact.size());
    EXPECT_EQ(0, std::memcmp(one.compact.data(), many.compact.data(), one.compact.size() * sizeof(VrcCompactPiece)));
    EXPECT_EQ(0, std::memcmp(one.voxels.data(), many.voxels.data(), one.voxels.size() * sizeof(VrcVoxel)));
    EXPECT_EQ(one.lod[0].density, many.lod[0].density);
}

TEST(VrcModel, a_polyline_inside_one_voxel_is_one_piece_between_its_vertices) {
    const StyledLines lines =
        makeLines({{{glm::vec3(0, 0, 0), 0.01f, glm::vec4(1)},
                    {glm::vec3(0.01f, 0.005f, 0), 0.01f, glm::vec4(1)},
                    {glm::vec3(0.02f, 0, 0), 0.01f, glm::vec4(1)}},
                   {{glm::vec3(1, 1, 1), 0.01f, glm::vec4(1)}, {glm::vec3(1.001f, 1, 1), 0.01f, glm::vec4(1)}}});
    const VrcModel m = build(lines, 4, 0);
    ASSERT_EQ(m.pieceCount(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const VrcPiece p = m.piece(i);
        EXPECT_TRUE(p.vertexA);
        EXPECT_TRUE(p.vertexB);
    }
}

TEST(VrcLodVolume, extinction_of_one_line_is_eq1_length_times_opacity_times_projected_width) {
    // sigma = (pi / 2) r l alpha / s^3 per voxel: a line of length 1, radius 0.01, alpha 0.4 has a
    // total sigma x volume of (pi / 2) 0.01 0.4 at every level, a voxel it crosses whole
    // (pi / 2) r s alpha / s^3, and the colour comes back as rgb x sigma / sigma.
    const glm::vec4 color(0.2f, 0.5f, 0.9f, 0.4f);
    const StyledLines lines = makeLines({{{glm::vec3(0, 0, 0), 0.01f, color}, {glm::vec3(1, 0, 0), 0.01f, color}}});
    for (int q : {0, 32}) {
        const VrcModel m = build(lines, 11, q);
        const std::vector<VrcLodLevel> levels = buildVrcLodVolume(m, false);
        const double pi = 3.14159265358979323846;
        const double expected = 0.5 * pi * 0.01 * 1.0 * 0.4;
        ASSERT_GE(levels.size(), 4u);
        for (std::size_t l = 0; l < levels.size(); ++l) {
            EXPECT_NEAR(levels[l].total(), expected, 1e-3 * expected) << "level " << l << " q " << q;
            EXPECT_FLOAT_EQ(levels[l].voxelSize, m.voxelSize * float(1 << l));
            if (l > 0) {
                EXPECT_EQ(levels[l].size, (levels[l - 1].size + 1) / 2);
            }
        }
        EXPECT_EQ(levels.back().size, glm::ivec3(1));
        // A voxel in the middle of the line, crossed whole (q > 0 snaps the ends to bin centres
        // of the x faces, which keeps the length 1 voxel).
        const glm::ivec3 mid = glm::ivec3((glm::vec3(0.5f, 0, 0) - m.origin) / m.voxelSize);
        const glm::vec4 v = levels[0].value[m.index(mid.x, mid.y, mid.z)];
        const double s = m.voxelSize;
        EXPECT_NEAR(v.w, 0.5 * pi * 0.01 * s * 0.4 / (s * s * s), 1e-3 * v.w);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c] / v.w, color[c], 2.0 / 255.0);
        // Opaque: alpha 1 for every tube.
        EXPECT_NEAR(buildVrcLodVolume(m, true)[0].total(), expected / 0.4, 1e-3 * expected / 0.4);
    }
}

TEST(VrcLodVolume, copies_are_not_counted_and_totals_hold_on_random_curves) {
    const StyledLines lines = makeLines(randomCurves(7, 40, 30, 0.08f));
    VrcBuildOptions o;
    o.resolution = 24;
    o.quantization = 0;
    const VrcModel plain = buildVrcModel(lines, o);
    o.dilate = true;
    const VrcModel dilated = buildVrcModel(lines, o);
    ASSERT_GT(dilated.copies, 0u);
    const std::vector<VrcLodLevel> a = buildVrcLodVolume(plain, false), b = buildVrcLodVolume(dilated, false);
    ASSERT_EQ(a.size(), b.size());
    // The sum over the pieces, independently of the volume.
    double expected = 0;
    for (std::size_t i = 0; i < plain.pieceCount(); ++i) {
        const VrcPiece p = plain.piece(i);
        expected += 0.5 * 3.14159265358979323846 * 0.5 * (p.ra + p.rb) * glm::length(p.b - p.a) * p.color.w;
    }
    for (std::size_t l = 0; l < a.size(); ++l) {
        EXPECT_NEAR(a[l].total(), expected, 1e-4 * expected) << "level " << l;
        EXPECT_NEAR(b[l].total(), expected, 1e-4 * expected) << "level " << l;
    }
}

}  // namespace
}  // namespace tc
