#include "core/vrc_representative.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace tc {

namespace {

// A home piece in model grid coordinates (voxel v covers [v, v + 1)).
struct GridPiece {
    glm::dvec3 a, b;
    double weight;  // Eq. 1: chord length (model voxel lengths) x opacity
    double length;
    double radius;  // mean of the end radii
    glm::dvec4 color;
};

// Moves face point p (level grid coordinates, on face `face` of voxel v) to its bin centre.
glm::dvec3 snapToBin(glm::dvec3 p, glm::ivec3 v, std::uint32_t face, int q) {
    if (q <= 0) return p;
    const int axis = int(face / 2);
    for (int k = 0; k < 3; ++k) {
        if (k == axis) continue;
        const double u = p[k] - double(v[k]);
        const int bin = std::clamp(int(std::floor(u * q)), 0, q - 1);
        p[k] = double(v[k]) + (double(bin) + 0.5) / double(q);
    }
    return p;
}

struct GridLine {
    glm::dvec3 a, b;
    std::uint32_t faceA = 0, faceB = 0;
    bool valid = false;  // the voxel holds pieces
    double weight = 0, radius = 0;
    glm::dvec4 color{0.0};
};

// Steps 1-3 of the header comment for the pieces `ids` of level voxel v (level grid coordinates,
// scale = model voxels per level voxel).
GridLine representative(const std::vector<GridPiece>& pieces, const std::vector<std::uint32_t>& ids, glm::ivec3 v,
                        double scale, int q) {
    GridLine line;
    line.valid = true;
    double total = 0, totalLength = 0;
    std::uint32_t heaviest = ids.front();
    for (std::uint32_t i : ids) {
        total += pieces[i].weight;
        totalLength += pieces[i].length;
        const GridPiece& h = pieces[heaviest];
        if (pieces[i].weight > h.weight || (pieces[i].weight == h.weight && pieces[i].length > h.length)) heaviest = i;
    }
    const bool byWeight = total > 0.0;
    const bool byLength = !byWeight && totalLength > 0.0;
    const glm::dvec3 reference = pieces[heaviest].b - pieces[heaviest].a;
    glm::dvec3 a(0.0), b(0.0);
    double sum = 0;
    for (std::uint32_t i : ids) {
        const GridPiece& p = pieces[i];
        const double w = byWeight ? p.weight : byLength ? p.length : 1.0;
        const bool flip = glm::dot(p.b - p.a, reference) < 0.0;
        a += w * (flip ? p.b : p.a);
        b += w * (flip ? p.a : p.b);
        line.radius += w * p.radius;
        line.color += w * p.color;
        sum += w;
    }
    a /= sum;
    b /= sum;
    line.radius /= sum;
    line.color /= sum;
    line.weight = total;
    // Into level grid coordinates, then extend the line through the averages to the voxel faces.
    a /= scale;
    b /= scale;
    const glm::dvec3 d = b - a;
    const glm::dvec3 m = 0.5 * (a + b);
    if (glm::length(d) * scale < 1e-3) {
        // Only slivers (a line grazing a voxel edge or corner): no reliable direction. A point
        // line at the average, with no faces (kInteriorFace), so it connects to nothing.
        line.a = line.b = m;
        line.faceA = line.faceB = kInteriorFace;
        return line;
    }
    double tIn = -1e300, tOut = 1e300;
    int axisIn = 0, axisOut = 0;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) continue;
        double t0 = (double(v[k]) - m[k]) / d[k], t1 = (double(v[k]) + 1.0 - m[k]) / d[k];
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > tIn) {
            tIn = t0;
            axisIn = k;
        }
        if (t1 < tOut) {
            tOut = t1;
            axisOut = k;
        }
    }
    line.a = m + tIn * d;
    line.b = m + tOut * d;
    const std::uint32_t sideIn = d[axisIn] > 0 ? 0u : 1u, sideOut = d[axisOut] > 0 ? 1u : 0u;
    line.a[axisIn] = double(v[axisIn]) + double(sideIn);  // exactly on the face
    line.b[axisOut] = double(v[axisOut]) + double(sideOut);
    line.faceA = std::uint32_t(2 * axisIn) + sideIn;
    line.faceB = std::uint32_t(2 * axisOut) + sideOut;
    line.a = snapToBin(line.a, v, line.faceA, q);
    line.b = snapToBin(line.b, v, line.faceB, q);
    return line;
}

}  // namespace

std::vector<VrcRepresentativeLevel> buildRepresentativeLines(const VrcModel& model, int maxLevel) {
    std::vector<VrcRepresentativeLevel> levels;
    if (model.voxels.empty()) return levels;
    const int longest = std::max({model.size.x, model.size.y, model.size.z});
    int top = 0;
    while ((1 << top) < longest) ++top;
    maxLevel = std::clamp(maxLevel, 0, top);

    // Home pieces, decoded once.
    const std::size_t n = model.pieceCount();
    std::vector<GridPiece> pieces(n);
    std::vector<char> home(n);
    const glm::dvec3 origin(model.origin);
    const double h = model.voxelSize;
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        const VrcPiece p = model.piece(i);
        home[i] = !p.copy;
        GridPiece& g = pieces[i];
        g.a = (glm::dvec3(p.a) - origin) / h;
        g.b = (glm::dvec3(p.b) - origin) / h;
        g.length = glm::length(g.b - g.a);
        g.weight = g.length * double(p.color.w);
        g.radius = 0.5 * (double(p.ra) + double(p.rb));
        g.color = glm::dvec4(p.color);
    });

    for (int level = 0; level <= maxLevel; ++level) {
        const int s = 1 << level;
        VrcRepresentativeLevel out;
        out.level = level;
        out.size = (model.size + s - 1) / s;
        out.voxelSize = model.voxelSize * float(s);
        const std::size_t count = std::size_t(out.size.x) * out.size.y * out.size.z;
        std::vector<GridLine> lines(count);
        tbb::parallel_for(0, out.size.z, [&](int z) {
            std::vector<std::uint32_t> ids;
            for (int y = 0; y < out.size.y; ++y)
                for (int x = 0; x < out.size.x; ++x) {
                    const glm::ivec3 v(x, y, z);
                    ids.clear();
                    const glm::ivec3 lo = v * s, hi = glm::min(lo + s, model.size);
                    for (int mz = lo.z; mz < hi.z; ++mz)
                        for (int my = lo.y; my < hi.y; ++my)
                            for (int mx = lo.x; mx < hi.x; ++mx) {
                                const VrcVoxel& hd = model.voxels[model.index(mx, my, mz)];
                                for (std::uint32_t k = 0; k < (hd.count & kCountMask); ++k)
                                    if (home[hd.offset + k]) ids.push_back(hd.offset + k);
                            }
                    GridLine& line = lines[out.index(v)];
                    if (ids.empty()) {
                        line.a = line.b = glm::dvec3(v) + 0.5;
                        continue;
                    }
                    line = representative(pieces, ids, v, double(s), model.quantization);
                }
        });
        // Step 4: connect across shared faces. Each end lies on one face, and each face is shared
        // by exactly one pair of voxels, so the pairs write disjoint ends (parallel-safe).
        tbb::parallel_for(0, out.size.z, [&](int z) {
            for (int y = 0; y < out.size.y; ++y)
                for (int x = 0; x < out.size.x; ++x) {
                    const glm::ivec3 v(x, y, z);
                    GridLine& lv = lines[out.index(v)];
                    if (!lv.valid) continue;
                    for (int k = 0; k < 3; ++k) {
                        glm::ivec3 nb = v;
                        ++nb[k];
                        if (nb[k] >= out.size[k]) continue;
                        GridLine& ln = lines[out.index(nb)];
                        if (!ln.valid) continue;
                        const std::uint32_t high = std::uint32_t(2 * k + 1), low = std::uint32_t(2 * k);
                        glm::dvec3* pv = lv.faceA == high ? &lv.a : lv.faceB == high ? &lv.b : nullptr;
                        glm::dvec3* pn = ln.faceA == low ? &ln.a : ln.faceB == low ? &ln.b : nullptr;
                        if (!pv || !pn || glm::distance(*pv, *pn) > 0.5) continue;
                        const glm::dvec3 mid = snapToBin(0.5 * (*pv + *pn), v, high, model.quantization);
                        *pv = mid;
                        *pn = mid;
                    }
                }
        });
        out.lines.resize(count);
        const glm::dvec3 o(model.origin);
        const double hl = double(out.voxelSize);
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
            const GridLine& g = lines[i];
            VrcRepresentativeLine& r = out.lines[i];
            r.a = glm::vec3(o + g.a * hl);
            r.b = glm::vec3(o + g.b * hl);
            r.radius = float(g.radius);
            r.weight = float(g.weight);
            r.color = glm::vec4(g.color);
            r.faceA = g.faceA;
            r.faceB = g.faceB;
        });
        levels.push_back(std::move(out));
    }
    return levels;
}

}  // namespace tc
