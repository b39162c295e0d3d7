#include "core/voxel_density.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <glm/gtc/constants.hpp>
#include <memory>
#include <new>

#include "core/error.h"

namespace tc {

double DensityGrid::total() const {
    double sum = 0.0;
    for (float d : density) sum += d;
    return sum;
}

float DensityGrid::sample(const glm::vec3& worldPos) const {
    if (density.empty()) return 0.0f;
    // Lattice of voxel centres: centre of voxel i sits at origin + (i + 0.5) * voxelSize.
    const glm::vec3 c = (worldPos - origin) / voxelSize - 0.5f;
    const glm::vec3 base = glm::floor(c);
    const glm::vec3 f = c - base;
    const glm::ivec3 i0(base);
    auto at = [&](int x, int y, int z) -> float {
        if (x < 0 || y < 0 || z < 0 || x >= size.x || y >= size.y || z >= size.z) return 0.0f;
        return density[index(x, y, z)];
    };
    float result = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
        const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
        const float w = (dx ? f.x : 1.0f - f.x) * (dy ? f.y : 1.0f - f.y) * (dz ? f.z : 1.0f - f.z);
        if (w != 0.0f) result += w * at(i0.x + dx, i0.y + dy, i0.z + dz);
    }
    return result;
}

DensityGrid makeDensityGrid(const Bounds& bounds, int resolution) {
    TC_CHECK(!bounds.empty());
    TC_CHECK_OP(resolution, >=, 2);
    const glm::vec3 extent = bounds.extent();
    int longest = 0;
    for (int k = 1; k < 3; ++k)
        if (extent[k] > extent[longest]) longest = k;

    DensityGrid grid;
    grid.voxelSize = extent[longest] > 0.0f ? extent[longest] / float(resolution - 1) : 1.0f;
    for (int k = 0; k < 3; ++k) {
        // ceil + 1 gives at least half a voxel of margin on both sides (see the header); a
        // rounding error just above an integer only adds a voxel of margin.
        grid.size[k] = k == longest ? resolution : int(std::ceil(double(extent[k]) / grid.voxelSize)) + 1;
    }
    grid.origin = bounds.center() - 0.5f * glm::vec3(grid.size) * grid.voxelSize;
    grid.density.assign(grid.voxelCount(), 0.0f);
    return grid;
}

namespace {

// The 64-bit fixed-point accumulator in bricks of 8^3 voxels, one 4 KiB page each: a streamline
// steps through its neighbours in y and z within the same page and cache lines instead of
// 2 KiB / 512 KiB apart as in the x-fastest layout, which matters because each deposit is an
// atomic read-modify-write that cannot overlap its cache or TLB miss with the next one.
// calloc rather than a vector: large blocks come zeroed from the kernel (mmap), so there is no
// single-threaded memset of 128 MB at 256^3, pages are first touched by the thread depositing
// into them, and pages no tube reaches stay the shared zero page when read back.
class BrickedAccumulator {
public:
    static constexpr int kBrick = 8;

    explicit BrickedAccumulator(const glm::ivec3& size)
        : m_bricks((size + (kBrick - 1)) / kBrick),
          m_data(static_cast<std::int64_t*>(std::calloc(brickCount() * kBrickVoxels, sizeof(std::int64_t)))) {
        if (!m_data) throw std::bad_alloc();
    }

    std::size_t brickCount() const {
        return std::size_t(m_bricks.x) * std::size_t(m_bricks.y) * std::size_t(m_bricks.z);
    }
    glm::ivec3 bricks() const { return m_bricks; }
    std::size_t index(const glm::ivec3& v) const {
        const glm::ivec3 b = v / kBrick, l = v % kBrick;
        const std::size_t brick =
            (std::size_t(b.z) * std::size_t(m_bricks.y) + std::size_t(b.y)) * std::size_t(m_bricks.x) +
            std::size_t(b.x);
        return brick * kBrickVoxels + std::size_t((l.z * kBrick + l.y) * kBrick + l.x);
    }
    void add(std::size_t i, std::int64_t value) {
        std::atomic_ref<std::int64_t>(m_data.get()[i]).fetch_add(value, std::memory_order_relaxed);
    }
    std::int64_t operator[](std::size_t i) const { return m_data.get()[i]; }

private:
    static constexpr std::size_t kBrickVoxels = kBrick * kBrick * kBrick;
    struct Free {
        void operator()(std::int64_t* p) const { std::free(p); }
    };
    glm::ivec3 m_bricks;
    std::unique_ptr<std::int64_t[], Free> m_data;
};

// Holds back the last deposit so consecutive pieces in one voxel (the end of one segment and the
// start of the next along a streamline) cost one atomic add.
// Integer addition is associative, so merging does not change the result.
struct PendingDeposit {
    std::size_t index = ~std::size_t(0);
    std::int64_t amount = 0;

    void add(BrickedAccumulator& acc, std::size_t i, std::int64_t value) {
        if (i != index) {
            flush(acc);
            index = i;
        }
        amount += value;
    }
    void flush(BrickedAccumulator& acc) {
        if (amount != 0) acc.add(index, amount);
        amount = 0;
    }
};

// Deposits one segment's axis, clipped to the grid, into `acc`. Returns whether it was clipped.
// All arithmetic in double: the deposits then sum to the analytic volume to ~1e-15 relative,
// far below the fixed-point and float-conversion errors.
bool voxelizeSegment(const glm::vec4& pa, const glm::vec4& pb, float alphaA, float alphaB, const DensityGrid& grid,
                     BrickedAccumulator& acc, PendingDeposit& pending) {
    const glm::dvec3 origin(grid.origin);
    const double h = grid.voxelSize;
    // Grid coordinates: voxel v covers [v, v + 1) on each axis.
    const glm::dvec3 a = (glm::dvec3(glm::vec3(pa)) - origin) / h;
    const glm::dvec3 b = (glm::dvec3(glm::vec3(pb)) - origin) / h;
    const glm::dvec3 d = b - a;
    const glm::dvec3 size(grid.size);

    // Slab clipping of the axis s in [0,1] to the closed box [0, size].
    double s0 = 0.0, s1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (a[k] < 0.0 || a[k] > size[k]) return true;
            continue;
        }
        double t0 = (0.0 - a[k]) / d[k], t1 = (size[k] - a[k]) / d[k];
        if (t0 > t1) std::swap(t0, t1);
        s0 = std::max(s0, t0);
        s1 = std::min(s1, t1);
    }
    if (s0 > s1) return true;
    const bool clipped = s0 > 0.0 || s1 < 1.0;

    const double worldLength = glm::length(d) * h;
    if (worldLength == 0.0) return clipped;

    // f(s) = r(s)^2 a(s) is a cubic in s; Simpson's rule integrates cubics exactly, and unlike
    // the expanded antiderivative it has no cancellation on short pieces of long segments.
    const double ra = pa.w, dr = double(pb.w) - ra;
    const double oa = alphaA, dOpacity = double(alphaB) - oa;
    auto f = [&](double s) {
        const double r = ra + s * dr;
        return r * r * (oa + s * dOpacity);
    };
    // pi L / 6 / voxelSize^3, in fixed-point units.
    const double k = kDensityFixedPointScale * glm::pi<double>() * worldLength / (6.0 * h * h * h);

    const glm::dvec3 start = a + s0 * d;
    glm::ivec3 v;
    for (int i = 0; i < 3; ++i) {
        // floor: a point on a face belongs to the voxel with the larger index; the outer face
        // (coordinate == size) belongs to the last voxel.
        v[i] = std::clamp(int(std::floor(start[i])), 0, grid.size[i] - 1);
    }
    const VoxelWalk walk(a, d);

    double sCur = s0, fCur = f(s0);
    for (;;) {
        int axis;
        const double sNext = walk.nextFace(v, sCur, s1, axis);
        const double fNext = f(sNext);
        const double amount = k * (sNext - sCur) * (fCur + 4.0 * f(0.5 * (sCur + sNext)) + fNext);
        const auto fixed = static_cast<std::int64_t>(amount + 0.5);
        if (fixed != 0) pending.add(acc, acc.index(v), fixed);
        if (axis < 0) break;
        v[axis] += walk.step[axis];
        // Rounding at the clip boundary can put the last face crossing just before s1.
        if (v[axis] < 0 || v[axis] >= grid.size[axis]) break;
        sCur = sNext;
        fCur = fNext;
    }
    return clipped;
}

}  // namespace

void voxelizeLines(const StyledLines& lines, DensityGrid& grid, const RegionBox& owner) {
    TC_CHECK(grid.voxelSize > 0.0f);
    TC_CHECK_OP(lines.color.size(), ==, lines.positionRadius.size());
    const std::size_t voxels = grid.voxelCount();
    TC_CHECK_OP(voxels, >, std::size_t(0));

    BrickedAccumulator acc(grid.size);

    std::atomic<std::size_t> clamped{0};
    const std::size_t segments = lines.segmentCount();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, segments, 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          std::size_t localClamped = 0;
                          PendingDeposit pending;
                          for (std::size_t s = r.begin(); s != r.end(); ++s) {
                              const std::uint32_t ia = lines.segmentVertices[2 * s];
                              const std::uint32_t ib = lines.segmentVertices[2 * s + 1];
                              if (!owner.contains(glm::vec3(lines.positionRadius[ia]))) continue;
                              localClamped += voxelizeSegment(lines.positionRadius[ia], lines.positionRadius[ib],
                                                              lines.color[ia].w, lines.color[ib].w, grid, acc, pending);
                          }
                          pending.flush(acc);
                          clamped.fetch_add(localClamped, std::memory_order_relaxed);
                      });

    grid.density.resize(voxels);
    std::atomic<bool> overflow{false};
    const glm::ivec3 bricks = acc.bricks();
    constexpr int B = BrickedAccumulator::kBrick;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, acc.brickCount()),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t brick = r.begin(); brick != r.end(); ++brick) {
                              const glm::ivec3 b(int(brick % bricks.x), int(brick / bricks.x % bricks.y),
                                                 int(brick / bricks.x / bricks.y));
                              const glm::ivec3 lo = b * B, hi = glm::min(lo + B, grid.size);
                              const std::size_t base = acc.index(lo);
                              bool negative = false;
                              for (int z = lo.z; z < hi.z; ++z)
                                  for (int y = lo.y; y < hi.y; ++y) {
                                      const std::size_t row = base + std::size_t(((z - lo.z) * B + (y - lo.y)) * B);
                                      float* out = grid.density.data() + grid.index(lo.x, y, z);
                                      for (int x = 0; x < hi.x - lo.x; ++x) {
                                          const std::int64_t value = acc[row + std::size_t(x)];
                                          negative |= value < 0;
                                          // 2^-32 is exact: one rounding, in the float conversion.
                                          out[x] = float(double(value) * (1.0 / kDensityFixedPointScale));
                                      }
                                  }
                              // Every deposit is >= 0, so a negative sum means it wrapped past
                              // 2^63 (2^31 voxel volumes in one voxel).
                              if (negative) overflow.store(true, std::memory_order_relaxed);
                          }
                      });
    TC_CHECK(!overflow.load());
    grid.clampedSegments = clamped.load();
}

DensityGrid buildLineDensity(const StyledLines& lines, int resolution, const RegionSetup& region) {
    DensityGrid grid = makeDensityGrid(region.boundsOr(lines.bounds), resolution);
    voxelizeLines(lines, grid, region.densityOwner());
    if (region.reduceDensity) {
        const std::size_t voxels = grid.density.size();
        region.reduceDensity(grid.density);
        TC_CHECK_OP(grid.density.size(), ==, voxels);
    }
    return grid;
}

}  // namespace tc
