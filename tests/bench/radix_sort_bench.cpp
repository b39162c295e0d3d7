// The visibility sort alone: GPU radix sort (gl/radix_sort.h) against oneTBB's parallel_sort and
// std::sort of the same (uint32 key, uint32 value) pairs, in the same run. Prints a Markdown
// table for docs/performance.md. Run by scripts/bench/radix_sort.sh.
//
//   tubecast_radix_sort_bench [--sizes 100000,1000000,10000000] [--reps 5]
//                             [--digit-bits 8] [--lanes 32] [--items 128]
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/error.h"
#include "gl/context.h"
#include "gl/gl_api.h"
#include "gl/gpu_timer.h"
#include "gl/objects.h"
#include "gl/radix_sort.h"

namespace {

using namespace tc::bench;

struct Pair {
    std::uint32_t key, value;
};

template <class Sort>
double timeCpu(const std::vector<Pair>& input, int reps, Sort sort) {
    std::vector<double> times;
    for (int r = 0; r < reps; ++r) {
        std::vector<Pair> pairs = input;
        auto start = Clock::now();
        sort(pairs);
        times.push_back(msSince(start));
    }
    return median(times);
}

}  // namespace

int main(int argc, char** argv) try {
    std::vector<std::size_t> sizes = {100000, 1000000, 10000000};
    int reps = 5;
    tc::gl::RadixSort::Config config;
    for (int i = 1; i + 1 < argc; i += 2) {
        std::string flag = argv[i];
        if (flag == "--sizes")
            sizes = parseList(argv[i + 1]);
        else if (flag == "--reps")
            reps = std::atoi(argv[i + 1]);
        else if (flag == "--digit-bits")
            config.digitBits = std::atoi(argv[i + 1]);
        else if (flag == "--lanes")
            config.lanes = std::atoi(argv[i + 1]);
        else if (flag == "--items")
            config.itemsPerLane = std::atoi(argv[i + 1]);
        else {
            std::fprintf(stderr, "error: unknown option %s\n", argv[i]);
            return 2;
        }
    }

    tc::gl::Context context = tc::gl::Context::create({});
    tc::gl::RadixSort gpuSort = tc::gl::RadixSort::create(config);
    tc::gl::StageTimer timer;

    std::printf("%s, %s; %d threads for TBB; median of %d runs; random 32-bit keys, uint32 values\n",
                context.info().renderer.c_str(), context.info().version.c_str(),
                tbb::this_task_arena::max_concurrency(), reps);
    std::printf("GPU: %d-bit digits (%d passes), %d lanes x %d keys per workgroup\n\n", config.digitBits,
                32 / config.digitBits, config.lanes, config.itemsPerLane);
    std::printf(
        "| keys | GPU radix sort, GL timer (ms) | GPU, wall incl. glFinish (ms) | "
        "GPU Mkeys/s | tbb::parallel_sort (ms) | std::sort (ms) | TBB / GPU |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|---:|\n");
    for (std::size_t n : sizes) {
        std::mt19937 rng(static_cast<unsigned>(n));
        std::vector<std::uint32_t> keys(n), values(n);
        std::vector<Pair> pairs(n);
        for (std::size_t i = 0; i < n; ++i) {
            keys[i] = rng();
            values[i] = static_cast<std::uint32_t>(i);
            pairs[i] = {keys[i], values[i]};
        }
        tc::gl::Buffer keyBuffer = tc::gl::makeBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
        tc::gl::Buffer valueBuffer = tc::gl::makeBuffer(n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);

        std::vector<double> gpuMs, wallMs;
        for (int r = -1; r < reps; ++r) {  // r = -1: warm-up (scratch allocation, shader JIT)
            glNamedBufferSubData(keyBuffer.id(), 0, n * 4, keys.data());
            glNamedBufferSubData(valueBuffer.id(), 0, n * 4, values.data());
            glFinish();
            auto start = Clock::now();
            timer.begin("sort");
            gpuSort.sort(keyBuffer, valueBuffer, n);
            timer.end();
            glFinish();
            double wall = msSince(start);
            std::vector<tc::StageTime> times = timer.collect();
            if (r >= 0) {
                gpuMs.push_back(times.at(0).gpuMs);
                wallMs.push_back(wall);
            }
        }

        // The GPU result must be the stable order, or the timing means nothing.
        std::vector<Pair> expected = pairs;
        std::stable_sort(expected.begin(), expected.end(), [](const Pair& a, const Pair& b) { return a.key < b.key; });
        std::vector<std::uint32_t> gotKeys(n), gotValues(n);
        glGetNamedBufferSubData(keyBuffer.id(), 0, n * 4, gotKeys.data());
        glGetNamedBufferSubData(valueBuffer.id(), 0, n * 4, gotValues.data());
        for (std::size_t i = 0; i < n; ++i)
            if (gotKeys[i] != expected[i].key || gotValues[i] != expected[i].value) {
                std::fprintf(stderr, "error: GPU sort of %zu keys wrong at %zu\n", n, i);
                return 1;
            }

        auto byKey = [](const Pair& a, const Pair& b) { return a.key < b.key; };
        double tbbMs =
            timeCpu(pairs, reps, [&](std::vector<Pair>& p) { tbb::parallel_sort(p.begin(), p.end(), byKey); });
        double stdMs = timeCpu(pairs, reps, [&](std::vector<Pair>& p) { std::sort(p.begin(), p.end(), byKey); });
        double gpu = median(gpuMs), wall = median(wallMs);
        std::printf("| %zu | %.1f | %.1f | %.1f | %.1f | %.1f | %.2f |\n", n, gpu, wall, n / (wall * 1e3), tbbMs, stdMs,
                    tbbMs / wall);
        std::fflush(stdout);
    }
    return 0;
} catch (const tc::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return static_cast<int>(e.code());
}
