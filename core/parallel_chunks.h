#pragma once
// Element-wise loops and sums over long vectors, split into fixed chunks run with oneTBB. The
// opacity solver's vector work (a dozen passes over n doubles per product with Q) was serial:
// running it in chunks made a 128k-part solve 10-18 % faster (`tubecast_fragment_occlusion_bench
// FILE --solves 3` on a system saved by `tubecast_opacity_bench --parts 128000 --save-system FILE`).
// Eigen parallelises only matrix products (with OpenMP), not these passes, so they are spelled
// out here. The chunks are fixed by n alone and sums are combined in a fixed tree
// (parallel_deterministic_reduce), so every result is the same on any number of threads. Vectors
// shorter than two chunks run serially in one piece. No OpenGL.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#include <cstdint>

namespace tc {

// 16384 doubles (128 KB) per chunk: the per-chunk overhead of oneTBB (~microseconds) stays small
// against a pass over the chunk, and 8k-part problems run serially.
constexpr std::int64_t kVectorChunk = 16384;

// f(begin, end) for each chunk of [0, n); `chunk` items per chunk (e.g. kVectorChunk / m for
// polylines of m parts).
template <class F>
void forChunks(std::int64_t n, F&& f, std::int64_t chunk = kVectorChunk) {
    chunk = chunk < 1 ? 1 : chunk;
    if (n < 2 * chunk) {
        if (n > 0) f(std::int64_t(0), n);
        return;
    }
    tbb::parallel_for(
        tbb::blocked_range<std::int64_t>(0, n, chunk),
        [&](const tbb::blocked_range<std::int64_t>& r) { f(r.begin(), r.end()); }, tbb::simple_partitioner());
}

// The sum of f(begin, end, T& partial) over the chunks of [0, n), each chunk adding into a partial
// that starts at `identity`; `combine(a, b)` joins two partials (in a fixed order).
template <class T, class F, class Combine>
T reduceChunks(std::int64_t n, const T& identity, F&& f, Combine&& combine) {
    if (n < 2 * kVectorChunk) {
        T partial = identity;
        if (n > 0) f(std::int64_t(0), n, partial);
        return partial;
    }
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::int64_t>(0, n, kVectorChunk), identity,
        [&](const tbb::blocked_range<std::int64_t>& r, T partial) {
            f(r.begin(), r.end(), partial);
            return partial;
        },
        combine, tbb::simple_partitioner());
}

// sum over i of f(i).
template <class F>
double sumChunks(std::int64_t n, F&& f) {
    return reduceChunks(
        n, 0.0,
        [&](std::int64_t begin, std::int64_t end, double& sum) {
            for (std::int64_t i = begin; i < end; ++i) sum += f(i);
        },
        [](double a, double b) { return a + b; });
}

}  // namespace tc
