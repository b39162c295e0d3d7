#include "core/vrc_model.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_scan.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/voxel_density.h"

namespace tc {

double VrcDensityLevel::total() const {
    double sum = 0.0;
    for (float d : density) sum += d;
    return sum;
}

double VrcLodLevel::total() const {
    double sum = 0.0;
    for (const glm::vec4& v : value) sum += v.w;
    return sum * double(voxelSize) * double(voxelSize) * double(voxelSize);
}

std::size_t VrcModel::lodBytes() const {
    std::size_t bytes = 0;
    for (const VrcDensityLevel& level : lod) bytes += level.density.size() * sizeof(float);
    return bytes;
}

namespace {

// In-plane axes of a face normal to `axis`, in increasing order.
glm::ivec2 planeAxes(int axis) {
    return axis == 0 ? glm::ivec2(1, 2) : axis == 1 ? glm::ivec2(0, 2) : glm::ivec2(0, 1);
}

int interiorLattice(int q) {
    return std::min(q, kInteriorLattice);
}

std::uint32_t packColor(glm::vec4 c) {
    std::uint32_t packed = 0;
    for (int i = 0; i < 4; ++i) {
        const float v = std::clamp(c[i], 0.0f, 1.0f);
        packed |= std::uint32_t(std::lround(v * 255.0f)) << (8 * i);
    }
    return packed;
}

glm::vec4 unpackColor(std::uint32_t p) {
    return {float(p & 0xFFu) / 255.0f, float((p >> 8) & 0xFFu) / 255.0f, float((p >> 16) & 0xFFu) / 255.0f,
            float(p >> 24) / 255.0f};
}

std::uint32_t packRadius(float r, float maxRadius) {
    const float f = maxRadius > 0.0f ? std::clamp(r / maxRadius, 0.0f, 1.0f) : 0.0f;
    return std::uint32_t(std::lround(f * 65535.0f));
}

// A piece as the walk produces it, in grid coordinates (voxel v covers [v, v + 1)).
struct RawPiece {
    std::uint32_t voxel;
    glm::ivec3 v;
    glm::dvec3 a, b;
    std::uint32_t faceA, faceB;
    float ra, rb;
    glm::vec4 ca, cb;
    std::uint32_t line;
    double weightedLength;  // Eq. 1: polyline length inside the voxel (voxel units) x mean opacity
};

// Walks polyline [first, last] through the grid and calls emit(RawPiece) for each piece, in order.
// Returns how many vertices were outside the grid (moved onto its boundary).
template <class Emit>
std::size_t walkPolyline(const StyledLines& lines, std::uint32_t first, std::uint32_t last, const DensityGrid& grid,
                         Emit&& emit) {
    const glm::dvec3 origin(grid.origin);
    const double h = grid.voxelSize;
    const glm::dvec3 hi = glm::dvec3(grid.size);
    std::size_t clamped = 0;
    auto gridPos = [&](std::uint32_t i) {
        glm::dvec3 p = (glm::dvec3(glm::vec3(lines.positionRadius[i])) - origin) / h;
        // Keep every vertex strictly inside the grid: the face at `size` belongs to no voxel.
        const glm::dvec3 q = glm::clamp(p, glm::dvec3(0.0), hi * (1.0 - 1e-12));
        if (q != p) ++clamped;
        return q;
    };
    auto voxelOf = [&](const glm::dvec3& p) {
        return glm::clamp(glm::ivec3(glm::floor(p)), glm::ivec3(0), grid.size - 1);
    };
    auto indexOf = [&](const glm::ivec3& v) {
        return std::uint32_t((std::size_t(v.z) * std::size_t(grid.size.y) + std::size_t(v.y)) *
                                 std::size_t(grid.size.x) +
                             std::size_t(v.x));
    };

    const std::uint32_t line = lines.polylineId[first];
    glm::dvec3 a = gridPos(first);
    glm::ivec3 v = voxelOf(a);
    RawPiece piece{};
    piece.v = v;
    piece.a = a;
    piece.faceA = kInteriorFace;
    piece.ra = lines.positionRadius[first].w;
    piece.ca = lines.color[first];
    piece.line = line;
    double length = 0.0, alphaLength = 0.0;

    auto finish = [&](const glm::dvec3& end, std::uint32_t face, float r, glm::vec4 c) {
        piece.b = end;
        piece.faceB = face;
        piece.rb = r;
        piece.cb = c;
        piece.voxel = indexOf(piece.v);
        piece.weightedLength = alphaLength;
        // Crossings through an edge or corner visit a neighbour for no distance: nothing to draw.
        if (length > 0.0 || piece.a != piece.b) emit(piece);
        length = alphaLength = 0.0;
    };

    for (std::uint32_t i = first; i < last; ++i) {
        const glm::dvec3 b = gridPos(i + 1);
        const glm::dvec3 d = b - a;
        const double segLength = glm::length(d);
        const glm::vec4 pa = lines.positionRadius[i], pb = lines.positionRadius[i + 1];
        const glm::vec4 ca = lines.color[i], cb = lines.color[i + 1];
        const VoxelWalk walk(a, d);
        const glm::ivec3 step = walk.step;
        double s = 0.0;
        for (;;) {
            int axis;
            const double sNext = walk.nextFace(v, s, 1.0, axis);
            const double ds = (sNext - s) * segLength;
            const double alphaMid = ca.w + (cb.w - ca.w) * 0.5 * (s + sNext);
            length += ds;
            alphaLength += ds * alphaMid;
            if (axis < 0) break;
            const glm::ivec3 next =
                v + glm::ivec3(axis == 0 ? step.x : 0, axis == 1 ? step.y : 0, axis == 2 ? step.z : 0);
            // Vertices are inside the grid, so a crossing out of it is float rounding at the far
            // end of a segment ending on the boundary: stay.
            if (next[axis] < 0 || next[axis] >= grid.size[axis]) break;
            glm::dvec3 x = a + sNext * d;
            x[axis] = step[axis] > 0 ? v[axis] + 1 : v[axis];  // exactly on the face
            const float r = float(pa.w + (pb.w - pa.w) * sNext);
            const glm::vec4 c = glm::mix(ca, cb, float(sNext));
            finish(x, std::uint32_t(2 * axis + (step[axis] > 0 ? 1 : 0)), r, c);
            v = next;
            piece.v = v;
            piece.a = x;
            piece.faceA = std::uint32_t(2 * axis + (step[axis] > 0 ? 0 : 1));
            piece.ra = r;
            piece.ca = c;
            s = sNext;
        }
        a = b;
    }
    finish(a, kInteriorFace, lines.positionRadius[last].w, lines.color[last]);
    return clamped;
}

// Grid-space position of code `code` in voxel `v`.
glm::dvec3 decodeGrid(int q, glm::ivec3 v, std::uint32_t code) {
    const std::uint32_t face = code >> kBinBits, bin = code & kBinMask;
    glm::dvec3 p(v);
    if (face == kInteriorFace) {
        const int m = interiorLattice(q);
        const glm::ivec3 cell(int(bin % m), int(bin / m % m), int(bin / m / m));
        return p + (glm::dvec3(cell) + 0.5) / double(m);
    }
    const int axis = int(face / 2);
    const glm::ivec2 plane = planeAxes(axis);
    p[axis] += double(face & 1u);
    p[plane.x] += (double(bin % std::uint32_t(q)) + 0.5) / q;
    p[plane.y] += (double(bin / std::uint32_t(q)) + 0.5) / q;
    return p;
}

std::uint32_t encodeGrid(int q, glm::ivec3 v, std::uint32_t face, const glm::dvec3& p) {
    const glm::dvec3 local = p - glm::dvec3(v);
    if (face == kInteriorFace) {
        const int m = interiorLattice(q);
        const glm::ivec3 cell = glm::clamp(glm::ivec3(glm::floor(local * double(m))), glm::ivec3(0), glm::ivec3(m - 1));
        return (face << kBinBits) | std::uint32_t((cell.z * m + cell.y) * m + cell.x);
    }
    const glm::ivec2 plane = planeAxes(int(face / 2));
    const int u = std::clamp(int(std::floor(local[plane.x] * q)), 0, q - 1);
    const int w = std::clamp(int(std::floor(local[plane.y] * q)), 0, q - 1);
    return (face << kBinBits) | std::uint32_t(w * q + u);
}

}  // namespace

glm::vec3 decodeEnd(const VrcModel& model, glm::ivec3 voxel, std::uint32_t code) {
    return glm::vec3(glm::dvec3(model.origin) + decodeGrid(model.quantization, voxel, code) * double(model.voxelSize));
}

std::uint32_t encodeEnd(const VrcModel& model, glm::ivec3 voxel, std::uint32_t face, glm::vec3 p) {
    return encodeGrid(model.quantization, voxel, face,
                      (glm::dvec3(p) - glm::dvec3(model.origin)) / double(model.voxelSize));
}

float vrcFaceQuantizationBound(const VrcModel& model) {
    return model.quantization > 0 ? 0.5f * std::sqrt(2.0f) * model.voxelSize / float(model.quantization) : 0.0f;
}

float vrcVertexQuantizationBound(const VrcModel& model) {
    return model.quantization > 0
               ? 0.5f * std::sqrt(3.0f) * model.voxelSize / float(interiorLattice(model.quantization))
               : 0.0f;
}

VrcPiece VrcModel::piece(std::size_t i) const {
    VrcPiece p{};
    if (quantization == 0) {
        const VrcExactPiece& e = exact[i];
        p.a = glm::vec3(e.a);
        p.b = glm::vec3(e.b);
        p.ra = e.a.w;
        p.rb = e.b.w;
        p.color = e.color;
        p.line = e.info.x;
        p.vertexA = (e.info.y & 1u) != 0;
        p.vertexB = (e.info.y & 2u) != 0;
        p.copy = e.info.z != 0;
        return p;
    }
    const VrcCompactPiece& c = compact[i];
    // The home voxel of a copy: integer first, so a copy decodes bit-identically to its original.
    const std::uint32_t offsetBits = c.line >> kLineBits;
    const glm::ivec3 v = coords(pieceVoxel[i]) + decodeHomeOffset(offsetBits);
    p.copy = offsetBits != 0;
    const std::uint32_t codeA = c.ends & 0xFFFFu, codeB = c.ends >> 16;
    p.a = decodeEnd(*this, v, codeA);
    p.b = decodeEnd(*this, v, codeB);
    p.ra = maxRadius * float(c.radius & 0xFFFFu) / 65535.0f;
    p.rb = maxRadius * float(c.radius >> 16) / 65535.0f;
    p.color = unpackColor(c.color);
    p.line = c.line & kLineMask;
    p.vertexA = (codeA >> kBinBits) == kInteriorFace;
    p.vertexB = (codeB >> kBinBits) == kInteriorFace;
    return p;
}

std::vector<VrcDensityLevel> buildDensityPyramid(VrcDensityLevel level0) {
    std::vector<VrcDensityLevel> levels;
    levels.push_back(std::move(level0));
    while (glm::any(glm::greaterThan(levels.back().size, glm::ivec3(1)))) {
        const VrcDensityLevel& src = levels.back();
        VrcDensityLevel dst;
        dst.size = (src.size + 1) / 2;
        dst.density.assign(std::size_t(dst.size.x) * dst.size.y * dst.size.z, 0.0f);
        tbb::parallel_for(0, dst.size.z, [&](int z) {
            for (int y = 0; y < dst.size.y; ++y)
                for (int x = 0; x < dst.size.x; ++x) {
                    // Padding voxels (past an odd size) are empty: the average is the block sum / 8,
                    // so level total x 8 = the level below's total.
                    double sum = 0.0;
                    for (int dz = 0; dz < 2; ++dz)
                        for (int dy = 0; dy < 2; ++dy)
                            for (int dx = 0; dx < 2; ++dx) {
                                const glm::ivec3 s(2 * x + dx, 2 * y + dy, 2 * z + dz);
                                if (s.x >= src.size.x || s.y >= src.size.y || s.z >= src.size.z) continue;
                                sum += src.density[(std::size_t(s.z) * src.size.y + s.y) * src.size.x + s.x];
                            }
                    dst.density[(std::size_t(z) * dst.size.y + y) * dst.size.x + x] = float(sum / 8.0);
                }
        });
        levels.push_back(std::move(dst));
    }
    return levels;
}

void buildVrcHeaders(VrcModel& model) {
    const std::size_t total = model.pieceVoxel.size();
    model.voxels.assign(model.voxelCount(), VrcVoxel{0, 0});
    // Headers: runs of equal voxel ids in the sorted order.
    for (std::size_t i = 0; i < total;) {
        const std::uint32_t v = model.pieceVoxel[i];
        std::size_t j = i;
        while (j < total && model.pieceVoxel[j] == v) ++j;
        model.voxels[v] = VrcVoxel{std::uint32_t(i), std::uint32_t(j - i)};
        i = j;
    }
    // Neighbourhood bit: lets the ray caster skip voxels whose whole 3x3x3 block is empty when it
    // tests neighbouring voxels' pieces (render.vrc.neighbors).
    const glm::ivec3 size = model.size;
    tbb::parallel_for(0, size.z, [&](int z) {
        for (int y = 0; y < size.y; ++y)
            for (int x = 0; x < size.x; ++x) {
                bool any = false;
                for (int dz = -1; dz <= 1 && !any; ++dz)
                    for (int dy = -1; dy <= 1 && !any; ++dy)
                        for (int dx = -1; dx <= 1 && !any; ++dx) {
                            const glm::ivec3 n(x + dx, y + dy, z + dz);
                            if (glm::any(glm::lessThan(n, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(n, size)))
                                continue;
                            any = (model.voxels[model.index(n.x, n.y, n.z)].count & kCountMask) != 0;
                        }
                if (any) model.voxels[model.index(x, y, z)].count |= kNeighbourhoodBit;
            }
    });
}

namespace {

// Segment [a, b] meets the box [lo, hi] (slab test, grid coordinates).
bool segmentMeetsBox(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& lo, const glm::dvec3& hi) {
    double s0 = 0.0, s1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        const double d = b[k] - a[k];
        if (d == 0.0) {
            if (a[k] < lo[k] || a[k] > hi[k]) return false;
            continue;
        }
        double ta = (lo[k] - a[k]) / d, tb = (hi[k] - a[k]) / d;
        if (ta > tb) std::swap(ta, tb);
        s0 = std::max(s0, ta);
        s1 = std::min(s1, tb);
        if (s0 > s1) return false;
    }
    return true;
}

}  // namespace

void dilateVrcModel(VrcModel& model, float reach) {
    TC_CHECK_OP(model.copies, ==, std::size_t(0));
    const std::size_t base = model.pieceCount();
    if (base == 0) return;
    const bool quantized = model.quantization > 0;
    const glm::ivec3 size = model.size;
    // Per piece: the 27-bit mask of the 3x3x3 block around its voxel (bit 13 = itself) that its
    // tube can reach.
    std::vector<std::uint32_t> masks(base);
    std::atomic<bool> lineTooLarge{false};
    tbb::parallel_for(std::size_t(0), base, [&](std::size_t i) {
        const VrcPiece p = model.piece(i);
        if (quantized && model.compact[i].line > kLineMask) lineTooLarge = true;
        const glm::ivec3 v = model.coords(model.pieceVoxel[i]);
        const glm::dvec3 o(model.origin);
        const double h = model.voxelSize;
        const glm::dvec3 a = (glm::dvec3(p.a) - o) / h, b = (glm::dvec3(p.b) - o) / h;
        // Grown by the larger radius (of the ring, with halos) and a little float slack (world
        // positions are floats).
        const double r = double(reach) * double(std::max(p.ra, p.rb)) / h;
        const double grow = r + 1e-4;
        // Joints: near a face end (within r along the axis) the tube coincides with the next or
        // previous piece of its polyline (exactly for collinear pieces, up to the outer wedge at a
        // bend), so one of the two suffices there: a piece is tested up to r before its end b (the
        // next piece covers the joint at its start), and against the voxel across its start a's
        // face (the previous piece's home, which holds that piece) also from r after a. Without
        // this, every piece would be copied into the ~4 neighbours around each joint (7 copies per
        // piece on the 10^6-segment tornado at resolution 128 instead of ~2).
        const double len = glm::length(b - a);
        const glm::dvec3 u = len > 0.0 ? (b - a) / len : glm::dvec3(0.0);
        const double sA = p.vertexA ? 0.0 : std::min(r, 0.5 * len);
        const double sB = p.vertexB ? len : std::max(len - r, 0.5 * len);
        const glm::dvec3 a1 = a, b1 = a + sB * u, a2 = a + sA * u;
        std::uint32_t mask = 1u << 13;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const glm::ivec3 d(dx, dy, dz), n = v + d;
                    if (d == glm::ivec3(0) || glm::any(glm::lessThan(n, glm::ivec3(0))) ||
                        glm::any(glm::greaterThanEqual(n, size)))
                        continue;
                    // The face neighbour whose shared face holds the start a.
                    bool acrossA = false;
                    if (!p.vertexA && std::abs(dx) + std::abs(dy) + std::abs(dz) == 1) {
                        const int k = dx != 0 ? 0 : dy != 0 ? 1 : 2;
                        const double facePlane = double(v[k]) + (d[k] > 0 ? 1.0 : 0.0);
                        acrossA = std::abs(a[k] - facePlane) < 1e-4;
                    }
                    if (segmentMeetsBox(acrossA ? a2 : a1, b1, glm::dvec3(n) - grow, glm::dvec3(n) + 1.0 + grow))
                        mask |= 1u << ((dz + 1) * 9 + (dy + 1) * 3 + (dx + 1));
                }
        masks[i] = mask;
    });
    if (lineTooLarge)
        throw InputError("render.vrc: a polyline id does not fit the " + std::to_string(kLineBits) +
                         " bits of a voxel copy; use render.vrc.neighbors: on");
    std::vector<std::uint64_t> offsets(base + 1, 0);
    for (std::size_t i = 0; i < base; ++i) offsets[i + 1] = offsets[i] + std::uint64_t(std::popcount(masks[i]));
    const std::uint64_t total = offsets[base];
    if (total >= (1ull << 31))
        throw InputError("render.vrc: the voxel model with copies would hold " + std::to_string(total) +
                         " pieces, more than 2^31; lower render.vrc.resolution or use render.vrc.neighbors: on");

    // Entry e (in (piece, offset) order) goes to voxel target[e]; a unique key per entry.
    std::vector<std::uint64_t> keys(total);
    std::vector<std::uint32_t> source(total), offsetBits(total);
    tbb::parallel_for(std::size_t(0), base, [&](std::size_t i) {
        std::uint64_t e = offsets[i];
        const glm::ivec3 v = model.coords(model.pieceVoxel[i]);
        for (int bit = 0; bit < 27; ++bit) {
            if (!(masks[i] & (1u << bit))) continue;
            const glm::ivec3 d(bit % 3 - 1, bit / 3 % 3 - 1, bit / 9 - 1);
            const glm::ivec3 n = v + d;
            keys[e] = (std::uint64_t(model.index(n.x, n.y, n.z)) << 32) | e;
            source[e] = std::uint32_t(i);
            offsetBits[e] = encodeHomeOffset(-d);  // home = storage - d
            ++e;
        }
    });
    tbb::parallel_sort(keys.begin(), keys.end());

    std::vector<VrcCompactPiece> compact;
    std::vector<VrcExactPiece> exact;
    if (quantized)
        compact.resize(total);
    else
        exact.resize(total);
    std::vector<std::uint32_t> pieceVoxel(total);
    tbb::parallel_for(std::uint64_t(0), total, [&](std::uint64_t k) {
        const std::uint64_t e = keys[k] & 0xFFFFFFFFu;
        const std::uint32_t i = source[e];
        pieceVoxel[k] = std::uint32_t(keys[k] >> 32);
        if (quantized) {
            compact[k] = model.compact[i];
            compact[k].line |= offsetBits[e] << kLineBits;
        } else {
            exact[k] = model.exact[i];
            exact[k].info.z = offsetBits[e];
        }
    });
    model.compact = std::move(compact);
    model.exact = std::move(exact);
    model.pieceVoxel = std::move(pieceVoxel);
    model.copies = total - base;
    buildVrcHeaders(model);
}

VrcModel emptyVrcModel(const StyledLines& lines, const VrcBuildOptions& options) {
    TC_CHECK_OP(options.resolution, >=, 2);
    TC_CHECK(options.quantization >= 0 && options.quantization <= kMaxQuantization);
    TC_CHECK_OP(lines.color.size(), ==, lines.positionRadius.size());
    VrcModel model;
    model.quantization = options.quantization;
    model.maxRadius = lines.maxRadius;
    if (lines.positionRadius.empty()) return model;
    const DensityGrid grid = makeDensityGrid(lines.bounds, options.resolution);
    model.size = grid.size;
    model.origin = grid.origin;
    model.voxelSize = grid.voxelSize;
    return model;
}

VrcModel buildVrcModel(const StyledLines& lines, const VrcBuildOptions& options) {
    VrcModel model = emptyVrcModel(lines, options);
    if (lines.positionRadius.empty()) return model;
    const DensityGrid grid = makeDensityGrid(lines.bounds, options.resolution);
    const int q = options.quantization;

    // Polylines: vertex ranges [FirstOfPolyline, LastOfPolyline].
    std::vector<std::uint32_t> firsts;
    for (std::uint32_t i = 0; i < lines.vertexCount(); ++i)
        if (lines.flags[i] & FirstOfPolyline) firsts.push_back(i);
    const std::size_t polylines = firsts.size();
    std::vector<std::uint32_t> lasts(polylines);
    tbb::parallel_for(std::size_t(0), polylines, [&](std::size_t p) {
        std::uint32_t i = firsts[p];
        while (!(lines.flags[i] & LastOfPolyline) && i + 1 < lines.vertexCount()) ++i;
        lasts[p] = i;
    });

    // Pass 1: pieces per polyline; exclusive scan gives each polyline's slot range, so pass 2
    // writes in a canonical order whatever the schedule.
    std::vector<std::uint64_t> offsets(polylines + 1, 0);
    tbb::parallel_for(std::size_t(0), polylines, [&](std::size_t p) {
        std::uint64_t n = 0;
        walkPolyline(lines, firsts[p], lasts[p], grid, [&](const RawPiece&) { ++n; });
        offsets[p + 1] = n;
    });
    for (std::size_t p = 0; p < polylines; ++p) offsets[p + 1] += offsets[p];
    const std::uint64_t total = offsets[polylines];
    if (total >= (1ull << 31))
        throw InputError("render.vrc: the voxel model would hold " + std::to_string(total) +
                         " pieces, more than 2^31; lower render.vrc.resolution");

    std::vector<VrcExactPiece> ordered(total);  // grid-space ends, before encoding
    std::vector<std::uint32_t> voxelOf(total);
    std::vector<double> weighted(total);
    std::atomic<std::size_t> clamped{0};
    tbb::parallel_for(std::size_t(0), polylines, [&](std::size_t p) {
        std::uint64_t slot = offsets[p];
        clamped += walkPolyline(lines, firsts[p], lasts[p], grid, [&](const RawPiece& r) {
            VrcExactPiece& e = ordered[slot];
            e.a = glm::vec4(glm::vec3(r.a), r.ra);
            e.b = glm::vec4(glm::vec3(r.b), r.rb);
            e.color = 0.5f * (r.ca + r.cb);
            e.info = glm::uvec4(r.line, 0u, 0u, 0u);
            if (q > 0) {
                // Encode from the double-precision position: the float copy above is only kept
                // for exact mode.
                e.info.z = encodeGrid(q, r.v, r.faceA, r.a) | (encodeGrid(q, r.v, r.faceB, r.b) << 16);
            } else {
                const glm::dvec3 o(grid.origin);
                e.a = glm::vec4(glm::vec3(o + r.a * double(grid.voxelSize)), r.ra);
                e.b = glm::vec4(glm::vec3(o + r.b * double(grid.voxelSize)), r.rb);
            }
            e.info.y = (r.faceA == kInteriorFace ? 1u : 0u) | (r.faceB == kInteriorFace ? 2u : 0u);
            voxelOf[slot] = r.voxel;
            weighted[slot] = r.weightedLength;
            ++slot;
        });
    });
    model.clampedVertices = clamped.load();

    // Sort by (voxel, canonical slot): the key makes the order unique, so parallel_sort's
    // instability does not matter.
    std::vector<std::uint64_t> keys(total);
    tbb::parallel_for(std::uint64_t(0), total,
                      [&](std::uint64_t i) { keys[i] = (std::uint64_t(voxelOf[i]) << 32) | i; });
    tbb::parallel_sort(keys.begin(), keys.end());

    const std::size_t voxels = model.voxelCount();
    model.voxels.assign(voxels, VrcVoxel{0, 0});
    model.pieceVoxel.resize(total);
    if (q > 0)
        model.compact.resize(total);
    else
        model.exact.resize(total);
    const float maxRadius = lines.maxRadius;
    tbb::parallel_for(std::uint64_t(0), total, [&](std::uint64_t i) {
        const std::uint64_t slot = keys[i] & 0xFFFFFFFFu;
        const VrcExactPiece& e = ordered[slot];
        model.pieceVoxel[i] = voxelOf[slot];
        if (q > 0) {
            model.compact[i] = VrcCompactPiece{e.info.z, e.info.x, packColor(e.color),
                                               packRadius(e.a.w, maxRadius) | (packRadius(e.b.w, maxRadius) << 16)};
        } else {
            model.exact[i] = e;
            model.exact[i].info.z = 0;
        }
    });
    buildVrcHeaders(model);

    if (options.lod) {
        VrcDensityLevel level0;
        level0.size = model.size;
        level0.density.assign(voxels, 0.0f);
        // Sum in sorted order per voxel: deterministic.
        tbb::parallel_for(std::size_t(0), voxels, [&](std::size_t v) {
            const VrcVoxel& h = model.voxels[v];
            double sum = 0.0;
            for (std::uint32_t k = 0; k < (h.count & kCountMask); ++k)
                sum += weighted[keys[h.offset + k] & 0xFFFFFFFFu];
            level0.density[v] = float(sum);
        });
        model.lod = buildDensityPyramid(std::move(level0));
    }
    if (options.dilate) dilateVrcModel(model, options.reach);
    return model;
}

std::vector<VrcLodLevel> buildVrcLodVolume(const VrcModel& model, bool opaque) {
    std::vector<VrcLodLevel> levels;
    if (model.voxels.empty()) return levels;
    VrcLodLevel level0;
    level0.size = model.size;
    level0.voxelSize = model.voxelSize;
    level0.value.assign(model.voxelCount(), glm::vec4(0.0f));
    const double s = model.voxelSize, volume = s * s * s;
    const double halfPi = 0.5 * 3.14159265358979323846;
    // Pieces are stored per voxel (headers): one task per voxel sums its home pieces in order.
    tbb::parallel_for(std::size_t(0), model.voxelCount(), [&](std::size_t v) {
        const VrcVoxel& h = model.voxels[v];
        glm::dvec4 sum(0.0);
        for (std::uint32_t k = 0; k < (h.count & kCountMask); ++k) {
            const VrcPiece p = model.piece(h.offset + k);
            if (p.copy) continue;
            const double alpha = opaque ? 1.0 : double(p.color.w);
            const double sigma = halfPi * 0.5 * double(p.ra + p.rb) * double(glm::length(p.b - p.a)) * alpha / volume;
            sum += glm::dvec4(glm::dvec3(p.color) * sigma, sigma);
        }
        level0.value[v] = glm::vec4(sum);
    });
    levels.push_back(std::move(level0));
    while (glm::any(glm::greaterThan(levels.back().size, glm::ivec3(1)))) {
        const VrcLodLevel& fine = levels.back();
        VrcLodLevel coarse;
        coarse.size = (fine.size + 1) / 2;
        coarse.voxelSize = 2.0f * fine.voxelSize;
        coarse.value.assign(std::size_t(coarse.size.x) * coarse.size.y * coarse.size.z, glm::vec4(0.0f));
        tbb::parallel_for(0, coarse.size.z, [&](int z) {
            for (int y = 0; y < coarse.size.y; ++y)
                for (int x = 0; x < coarse.size.x; ++x) {
                    glm::vec4 sum(0.0f);
                    for (int dz = 0; dz < 2; ++dz)
                        for (int dy = 0; dy < 2; ++dy)
                            for (int dx = 0; dx < 2; ++dx) {
                                const glm::ivec3 c(2 * x + dx, 2 * y + dy, 2 * z + dz);
                                if (glm::any(glm::greaterThanEqual(c, fine.size))) continue;  // zero padding
                                sum += fine.value[(std::size_t(c.z) * fine.size.y + c.y) * fine.size.x + c.x];
                            }
                    coarse.value[(std::size_t(z) * coarse.size.y + y) * coarse.size.x + x] = sum * 0.125f;
                }
        });
        levels.push_back(std::move(coarse));
    }
    return levels;
}

}  // namespace tc
