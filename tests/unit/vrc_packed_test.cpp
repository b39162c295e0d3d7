// The paper's packed VRC encoding (core/vrc_packed.h) against the 16-byte model it is packed from:
// round trip of every piece (face ends bit-identical, vertex ends within the re-snap bound,
// colour within the palette error and exact with <= 256 colours, radius within its unorm8 step),
// local line ids that tell the lines of a voxel apart exactly as the global ids do, the bytes per
// piece of Table I (Kanzler et al. 2019), the wider local line id (> 32 lines in a voxel) and
// count (> 255 pieces), and the fall-backs (> 4096 lines in a voxel, exact end points).
#include "core/vrc_packed.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include "core/vrc_model.h"
#include "test_scenes.h"

namespace tc {
namespace {

using Vertex = test::TestVertex;
constexpr auto makeLines = test::makeStyledLines;

// Random walks. `palette` > 0: colours drawn from that many fixed colours, else random per vertex;
// `radius` > 0: every vertex that radius, else random. std::mt19937's raw output only.
std::vector<std::vector<Vertex>> randomCurves(std::uint32_t seed, int count, int points, int palette, float radius) {
    std::mt19937 rng(seed);
    auto uniform = [&] { return float(rng()) / 4294967296.0f; };
    std::vector<glm::vec4> colors;
    for (int i = 0; i < palette; ++i) colors.emplace_back(uniform(), uniform(), uniform(), 0.2f + 0.8f * uniform());
    std::vector<std::vector<Vertex>> curves;
    for (int c = 0; c < count; ++c) {
        std::vector<Vertex> pl;
        glm::vec3 p(uniform() * 2 - 1, uniform() * 2 - 1, uniform() * 2 - 1);
        glm::vec3 dir = glm::normalize(glm::vec3(uniform() - 0.5f, uniform() - 0.5f, uniform() - 0.5f) + 1e-3f);
        const glm::vec4 lineColor = palette > 0 ? colors[rng() % std::uint32_t(palette)] : glm::vec4(0.0f);
        for (int i = 0; i < points; ++i) {
            const glm::vec4 col =
                palette > 0 ? lineColor : glm::vec4(uniform(), uniform(), uniform(), 0.2f + 0.8f * uniform());
            pl.push_back({p, radius > 0.0f ? radius : 0.005f + 0.02f * uniform(), col});
            dir = glm::normalize(dir + 0.8f * glm::vec3(uniform() - 0.5f, uniform() - 0.5f, uniform() - 0.5f));
            p += 0.08f * (0.3f + uniform()) * dir;
        }
        curves.push_back(pl);
    }
    return curves;
}

VrcModel build(const StyledLines& lines, int resolution, int q, bool dilate) {
    VrcBuildOptions o;
    o.resolution = resolution;
    o.quantization = q;
    o.lod = false;
    o.dilate = dilate;
    return buildVrcModel(lines, o);
}

std::uint32_t channelOf(glm::vec4 c, int k) {
    return std::uint32_t(std::lround(c[k] * 255.0f));
}

// Checks every piece of `packed` against `model`'s; `vertexBound` the allowed vertex end error.
void expectRoundTrip(const VrcModel& model, const VrcPackedModel& packed, bool exactColors, bool exactRadius) {
    ASSERT_EQ(packed.pieceCount, model.pieceCount());
    const float vertexBound = vrcPaperVertexResnapBound(packed) * 1.0001f + 1e-6f;
    const float radiusStep = model.maxRadius / 510.0f * 1.0001f + 1e-7f;
    std::size_t vertexEnds = 0;
    for (std::size_t v = 0; v < model.voxelCount(); ++v) {
        const std::uint32_t count = model.voxels[v].count & kCountMask;
        ASSERT_EQ(packed.counts[v], count);
        if (count) {
            ASSERT_EQ(packed.offsets[v], model.voxels[v].offset);
        }
        for (std::uint32_t k = 0; k < count; ++k) {
            const std::size_t i = model.voxels[v].offset + k;
            const VrcPiece ref = model.piece(i), got = unpackVrcPiece(packed, v, i);
            ASSERT_EQ(got.vertexA, ref.vertexA);
            ASSERT_EQ(got.vertexB, ref.vertexB);
            ASSERT_EQ(got.copy, ref.copy);
            for (auto [g, r, vertex] : {std::tuple{got.a, ref.a, ref.vertexA}, std::tuple{got.b, ref.b, ref.vertexB}}) {
                if (vertex) {
                    ++vertexEnds;
                    EXPECT_LE(glm::length(g - r), vertexBound) << "piece " << i;
                    if (vertexBound < 1e-5f) {
                        EXPECT_EQ(g, r);
                    }
                } else {
                    ASSERT_EQ(g, r) << "piece " << i;  // bit-identical
                }
            }
            if (exactRadius) {
                EXPECT_EQ(got.ra, ref.ra);
                EXPECT_EQ(got.rb, ref.rb);
            } else {
                EXPECT_LE(std::abs(got.ra - ref.ra), radiusStep);
                EXPECT_LE(std::abs(got.rb - ref.rb), radiusStep);
            }
            for (int c = 0; c < 4; ++c) {
                const int d = int(channelOf(got.color, c)) - int(channelOf(ref.color, c));
                if (exactColors)
                    ASSERT_EQ(d, 0);
                else
                    ASSERT_LE(std::abs(d), packed.paletteMaxError);
            }
            EXPECT_EQ(packed.globalIds[i], ref.line);
            // Local ids tell this voxel's lines apart exactly as the global ids.
            for (std::uint32_t k2 = 0; k2 < k; ++k2) {
                const std::size_t j = model.voxels[v].offset + k2;
                EXPECT_EQ(unpackVrcPiece(packed, v, j).line == got.line, model.piece(j).line == ref.line);
            }
        }
    }
    EXPECT_GT(vertexEnds, 0u);
}

TEST(VrcPacked, table_one_bytes_per_piece) {
    // Kanzler et al. 2019, Table I: (4, 8) -> 4 bytes, (16, 32) -> 5, (64, 128) -> 6, one radius,
    // no copies. q = 128 exceeds the model's codes (kMaxQuantization); 64 stands for its row.
    for (auto [q, bytes] : {std::pair{4, 4}, std::pair{8, 4}, std::pair{16, 5}, std::pair{32, 5}, std::pair{64, 6}})
        EXPECT_EQ(vrcPaperLayout(q, false, false).bytesPerPiece(), bytes) << "q = " << q;
    EXPECT_EQ(vrcPaperLayout(32, false, false).bitsPerPiece(), 39);
    EXPECT_EQ(vrcPaperLayout(32, true, false).bytesPerPiece(), 6);  // 45 bits with the home offset
    EXPECT_EQ(vrcPaperLayout(32, false, true).bytesPerPiece(), 7);  // 55 bits with two unorm8 radii
    EXPECT_EQ(vrcPaperLayout(90, true, true).bitsPerPiece(), 2 * 17 + 8 + 5 + 6 + 16);
}

TEST(VrcPacked, interior_lattice_fits_the_two_spare_face_ids) {
    EXPECT_EQ(vrcPaperInteriorLattice(4), 3);    // 27 <= 2^5
    EXPECT_EQ(vrcPaperInteriorLattice(8), 5);    // 125 <= 2^7
    EXPECT_EQ(vrcPaperInteriorLattice(16), 8);   // 512 <= 2^9
    EXPECT_EQ(vrcPaperInteriorLattice(32), 12);  // 1728 <= 2^11
    EXPECT_EQ(vrcPaperInteriorLattice(33), 16);  // the model's own lattice from here on
    EXPECT_EQ(vrcPaperInteriorLattice(64), 16);
    for (int q = 1; q <= kMaxQuantization; ++q) {
        const VrcPaperLayout l = vrcPaperLayout(q, false, false);
        const std::uint64_t cells = std::uint64_t(l.interiorLattice) * l.interiorLattice * l.interiorLattice;
        EXPECT_LE(cells, std::uint64_t(2) << l.binBits) << q;
        EXPECT_LE(std::uint64_t(q) * q, std::uint64_t(1) << l.binBits) << q;
    }
}

TEST(VrcPacked, constant_colour_and_radius_at_q64_with_copies_round_trips_bit_for_bit) {
    const StyledLines lines = makeLines(randomCurves(7, 30, 40, 1, 0.012f));
    const VrcModel model = build(lines, 24, 64, true);
    ASSERT_GT(model.copies, 0u);
    const VrcPackResult r = packVrcModel(model);
    ASSERT_TRUE(r.ok()) << r.reason;
    const VrcPackedModel& p = r.model;
    EXPECT_FALSE(p.layout.radiusVaries);
    EXPECT_TRUE(p.layout.copies);
    EXPECT_EQ(p.paletteSize, 1);
    EXPECT_EQ(p.paletteMaxError, 0);
    EXPECT_EQ(vrcPaperVertexResnapBound(p), 0.0f);
    EXPECT_EQ(p.layout.bytesPerPiece(), 7);  // 43 + 6 bits
    EXPECT_EQ(p.headerBytes(), model.voxelCount() * 5);
    EXPECT_EQ(p.pieceBytes(), model.pieceCount() * 7);
    expectRoundTrip(model, p, true, true);
}

TEST(VrcPacked, q32_without_copies_takes_five_bytes_and_with_copies_six) {
    const StyledLines lines = makeLines(randomCurves(8, 30, 40, 1, 0.012f));
    const VrcPackResult plain = packVrcModel(build(lines, 24, 32, false));
    const VrcPackResult copies = packVrcModel(build(lines, 24, 32, true));
    ASSERT_TRUE(plain.ok() && copies.ok());
    EXPECT_EQ(plain.model.layout.bytesPerPiece(), 5);
    EXPECT_EQ(copies.model.layout.bytesPerPiece(), 6);
    EXPECT_EQ(plain.model.pieceBytes(), plain.model.pieceCount * 5);
    EXPECT_GE(plain.model.bytes.size(), plain.model.pieceBytes() + 8);  // the ray caster reads 3 words
}

TEST(VrcPacked, varying_colours_and_radii_round_trip_within_palette_and_radius_steps) {
    // Random colour per vertex: far more than 256 distinct colours (median cut).
    const StyledLines lines = makeLines(randomCurves(9, 40, 40, 0, 0.0f));
    const VrcModel model = build(lines, 24, 32, true);
    const VrcPackResult r = packVrcModel(model);
    ASSERT_TRUE(r.ok()) << r.reason;
    const VrcPackedModel& p = r.model;
    EXPECT_TRUE(p.layout.radiusVaries);
    EXPECT_FALSE(p.paletteExact);
    EXPECT_EQ(p.paletteSize, 256);
    EXPECT_GT(p.paletteMaxError, 0);
    EXPECT_LT(p.paletteMaxError, 64);               // 256 boxes over a few thousand colours
    EXPECT_GT(vrcPaperVertexResnapBound(p), 0.0f);  // q = 32: the 12^3 lattice
    expectRoundTrip(model, p, false, false);
}

TEST(VrcPacked, at_most_256_colours_are_exact) {
    const StyledLines lines = makeLines(randomCurves(10, 60, 30, 200, 0.0f));
    const VrcModel model = build(lines, 20, 16, false);
    const VrcPackResult r = packVrcModel(model);
    ASSERT_TRUE(r.ok()) << r.reason;
    EXPECT_TRUE(r.model.paletteExact);
    EXPECT_EQ(r.model.paletteMaxError, 0);
    EXPECT_LE(r.model.paletteSize, 200);
    expectRoundTrip(model, r.model, true, false);
}

TEST(VrcPacked, palette_is_deterministic_and_within_its_reported_error) {
    std::mt19937 rng(3);
    std::vector<std::uint32_t> colors(20000);
    for (std::uint32_t& c : colors) c = rng();
    const VrcPalette a = vrcPaperPalette(colors), b = vrcPaperPalette(colors);
    EXPECT_EQ(a.colors, b.colors);
    EXPECT_EQ(a.index, b.index);
    ASSERT_EQ(a.colors.size(), 256u);
    int worst = 0;
    for (std::size_t i = 0; i < colors.size(); ++i)
        for (int k = 0; k < 4; ++k)
            worst = std::max(
                worst, std::abs(int((colors[i] >> (8 * k)) & 255u) - int((a.colors[a.index[i]] >> (8 * k)) & 255u)));
    EXPECT_EQ(worst, a.maxError);
    EXPECT_GT(worst, 0);
}

// The long diagonal line that sets the grid of the fall-back tests, and the part of voxel 0 inside
// its bounds (lo, hi), where the test lines go.
std::vector<Vertex> diagonal() {
    return {{glm::vec3(-1, -1, -1), 0.001f, glm::vec4(1)}, {glm::vec3(1, 1, 1), 0.001f, glm::vec4(1)}};
}
std::pair<glm::vec3, glm::vec3> voxelZeroInside(int resolution) {
    const VrcModel grid = build(makeLines({diagonal()}), resolution, 8, false);
    const glm::vec3 lo = glm::max(grid.origin, glm::vec3(-1.0f)) + 0.05f;
    const glm::vec3 hi = glm::min(grid.origin + grid.voxelSize, glm::vec3(1.0f)) - 0.05f;
    return {lo, hi};
}

std::uint32_t mostPieces(const VrcModel& m) {
    std::uint32_t most = 0;
    for (const VrcVoxel& h : m.voxels) most = std::max(most, h.count & kCountMask);
    return most;
}

TEST(VrcPacked, voxel_with_more_than_32_lines_widens_the_local_line_id) {
    // Short parallel lines inside voxel 0 (the diagonal crosses it too).
    const auto [lo, hi] = voxelZeroInside(4);
    ASSERT_TRUE(glm::all(glm::lessThan(lo, hi)));
    auto lines = [&, lo = lo, hi = hi](int n) {
        std::vector<std::vector<Vertex>> p{diagonal()};
        for (int i = 0; i < n; ++i) {
            const float y = lo.y + (hi.y - lo.y) * float(i) / float(n);
            p.push_back(
                {{glm::vec3(lo.x, y, lo.z), 0.001f, glm::vec4(1)}, {glm::vec3(hi.x, y, lo.z), 0.001f, glm::vec4(1)}});
        }
        return build(makeLines(p), 4, 8, false);
    };
    const VrcPackResult paper = packVrcModel(lines(31));  // 32 lines in voxel 0 with the diagonal
    ASSERT_TRUE(paper.ok()) << paper.reason;
    EXPECT_EQ(paper.model.layout.lineBits, 5);
    EXPECT_EQ(paper.wideLines, 0u);
    const VrcModel wide = lines(32);
    const VrcPackResult r = packVrcModel(wide);
    ASSERT_TRUE(r.ok()) << r.reason;
    EXPECT_EQ(r.model.layout.lineBits, 6);
    EXPECT_EQ(r.wideLines, 1u);
    EXPECT_EQ(r.model.layout.countBytes, 1);
    // The 33 local ids tell the lines apart as the global ones do (expectRoundTrip checks it).
    expectRoundTrip(wide, r.model, true, true);
    // Past the widest id the ray caster reads (2^12 lines in one voxel): the 16-byte encoding.
    const VrcPackResult most = packVrcModel(lines(1 << kPaperMaxLineBits));
    EXPECT_FALSE(most.ok());
    EXPECT_NE(most.reason.find("4096 distinct polylines"), std::string::npos) << most.reason;
    EXPECT_EQ(most.tooManyLines, 1u);
    EXPECT_EQ(most.tooManyPieces, 0u);
}

TEST(VrcPacked, voxel_with_more_than_255_pieces_takes_a_two_byte_count) {
    // One polyline zigzagging across the face x = origin + voxel size between voxel 0 and its x
    // neighbour: a piece per visit of each.
    const VrcModel grid = build(makeLines({diagonal()}), 4, 8, false);
    const float face = grid.origin.x + grid.voxelSize;
    const auto [lo, hi] = voxelZeroInside(4);
    auto zigzag = [&, lo = lo, hi = hi](int visits) {
        std::vector<Vertex> pl;
        for (int i = 0; i < visits; ++i)
            pl.push_back(
                {glm::vec3(face + (i % 2 ? 0.05f : -0.05f), lo.y + (hi.y - lo.y) * float(i) / float(visits), lo.z),
                 0.001f, glm::vec4(1)});
        return build(makeLines({diagonal(), pl}), 4, 8, false);
    };
    const VrcModel many = zigzag(600);
    ASSERT_GT(mostPieces(many), 255u);
    const VrcPackResult r = packVrcModel(many);
    ASSERT_TRUE(r.ok()) << r.reason;
    EXPECT_EQ(r.model.layout.countBytes, 2);
    EXPECT_EQ(r.model.headerBytes(), many.voxelCount() * 6);
    EXPECT_GE(r.widePieces, 1u);
    EXPECT_EQ(r.model.layout.lineBits, 5);  // two polylines
    expectRoundTrip(many, r.model, true, true);
    // The counts as the ray caster reads them: two per word.
    const std::vector<std::uint32_t> words = r.model.countWords();
    for (std::size_t v = 0; v < many.voxelCount(); ++v)
        ASSERT_EQ((words[v / 2] >> (16 * (v % 2))) & 0xFFFFu, many.voxels[v].count & kCountMask) << v;
    const VrcModel fewer = zigzag(400);
    ASSERT_LE(mostPieces(fewer), 255u);
    const VrcPackResult one = packVrcModel(fewer);
    ASSERT_TRUE(one.ok());
    EXPECT_EQ(one.model.layout.countBytes, 1);
    EXPECT_EQ(one.model.headerBytes(), fewer.voxelCount() * 5);
}

TEST(VrcPacked, exact_end_points_have_nothing_to_pack) {
    const StyledLines lines = makeLines(randomCurves(11, 5, 10, 1, 0.01f));
    const VrcPackResult r = packVrcModel(build(lines, 8, 0, false));
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.reason.find("quantization"), std::string::npos);
}

}  // namespace
}  // namespace tc
