// Loading speed of a line file through readLineSet (read + clean), e.g. a .tcb of 10^7 segments.
//
//     tubecast_line_read_bench FILE.tcb [--make LINES POINTS] [--repeat N]
//
// --make writes FILE first (a tornado of LINES x POINTS, through writeTcb). Each repetition
// first evicts FILE from the page cache (posix_fadvise DONTNEED: a cold read from disk without
// dropping the whole machine's cache), then times readLineSet; a second, warm read follows.
// Prints MB/s of file bytes for both, and the clean pass alone.
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/generators.h"
#include "core/line_set.h"
#include "io/line_formats.h"
#include "io/line_reader.h"

namespace {

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void evict(const std::string& path) {
    int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return;
    ::fdatasync(fd);
    ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
    ::close(fd);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE [--make LINES POINTS] [--repeat N]\n", argv[0]);
        return 2;
    }
    const std::string path = argv[1];
    int repeat = 3;
    for (int i = 2; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--make" && i + 2 < argc) {
            auto t0 = std::chrono::steady_clock::now();
            tc::LineSet lines = tc::generateTornado(std::atoi(argv[i + 1]), std::atoi(argv[i + 2]), 1);
            std::printf("generated %zu segments in %.2f s\n", lines.segmentCount(), seconds(t0));
            tc::writeTcb(lines, path);
            i += 2;
        } else if (a == "--repeat" && i + 1 < argc) {
            repeat = std::atoi(argv[++i]);
        }
    }
    const double mb = double(std::filesystem::file_size(path)) / 1e6;
    for (int r = 0; r < repeat; ++r) {
        evict(path);
        auto t0 = std::chrono::steady_clock::now();
        tc::LineSet lines = tc::readLineSet(path);
        const double cold = seconds(t0);
        t0 = std::chrono::steady_clock::now();
        lines = tc::readLineSet(path);
        const double warm = seconds(t0);
        t0 = std::chrono::steady_clock::now();
        tc::LineSet raw = tc::readNativeLineFile(path);
        const double readOnly = seconds(t0);
        t0 = std::chrono::steady_clock::now();
        tc::cleanLineSet(raw);
        const double clean = seconds(t0);
        std::printf(
            "%s: %.1f MB, %zu segments, %zu attributes: cold %.3f s (%.0f MB/s), warm %.3f s (%.0f MB/s); "
            "warm read without clean %.3f s (%.0f MB/s), clean %.3f s\n",
            path.c_str(), mb, lines.segmentCount(), lines.attributes.size(), cold, mb / cold, warm, mb / warm, readOnly,
            mb / readOnly, clean);
    }
    return 0;
}
