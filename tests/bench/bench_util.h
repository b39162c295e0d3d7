#pragma once
// Small helpers shared by the hand-rolled benchmark mains in tests/bench/. These benchmarks time
// whole GL frames and passes with GPU timer queries and print Markdown tables for
// docs/performance.md, which Google Benchmark's per-iteration model does not fit.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <vector>

namespace tc::bench {

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// "100000,1000000" -> {100000, 1000000}.
inline std::vector<std::size_t> parseList(const char* text) {
    std::vector<std::size_t> values;
    for (const char* p = text; *p;) {
        char* end = nullptr;
        values.push_back(std::size_t(std::strtoull(p, &end, 10)));
        if (end == p) break;
        p = *end == ',' ? end + 1 : end;
    }
    return values;
}

inline double megabytes(std::size_t bytes) {
    return double(bytes) / (1024.0 * 1024.0);
}

}  // namespace tc::bench
