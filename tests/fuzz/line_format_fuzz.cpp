// libFuzzer target for one line-format reader, chosen at compile time (TUBECAST_FUZZ_FORMAT =
// 1 trk, 2 tck, 3 tcb, 4 obj; tests/fuzz/CMakeLists.txt builds one binary per format).
// Any input must either read into a structurally valid LineSet or throw InputError; anything
// else (a crash, a sanitizer report, another exception, a huge allocation) is a finding.
#include <cstddef>
#include <cstdint>

#include "core/error.h"
#include "core/line_set.h"
#include "io/line_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    tc::MemorySource source("fuzz-input", data, size);
    try {
#if TUBECAST_FUZZ_FORMAT == 1
        tc::LineSet lines = tc::readTrk(source);
#elif TUBECAST_FUZZ_FORMAT == 2
        tc::LineSet lines = tc::readTck(source);
        // The same bytes as the scalars of the tracks just read: exercises the .tsf parser and
        // its length checks (almost always an InputError, which is fine).
        try {
            tc::readTsf(source, lines);
        } catch (const tc::InputError&) {
        }
#elif TUBECAST_FUZZ_FORMAT == 3
        tc::LineSet lines = tc::readTcb(source);
#elif TUBECAST_FUZZ_FORMAT == 4
        tc::LineSet lines = tc::readObjLines(source);
#else
#error "TUBECAST_FUZZ_FORMAT must be 1..4"
#endif
        // cleanLineSet checks the structure the readers promise (TC_CHECK throws a non-input
        // Error, which escapes and aborts the run).
        tc::cleanLineSet(lines);
    } catch (const tc::InputError&) {
    }
    return 0;
}
