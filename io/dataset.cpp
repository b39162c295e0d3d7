#include "io/dataset.h"

#include <chrono>

#include "core/error.h"
#include "core/generators.h"
#include "io/line_reader.h"

namespace tc {

DatasetLoad loadDataset(const DatasetSpec& spec) {
    auto start = std::chrono::steady_clock::now();
    DatasetLoad load;
    if (!spec.generate.empty()) {
        load.lines = generateTornado(spec.lines, spec.points, spec.seed);
        load.source = "generate:" + spec.generate + "(lines=" + std::to_string(spec.lines) +
                      ",points=" + std::to_string(spec.points) + ",seed=" + std::to_string(spec.seed) + ")";
    } else {
        load.lines = readLineSet(spec.path, &load.cleaned);
        load.source = spec.path;
    }
    if (load.lines.polylineCount() == 0)
        throw InputError(load.source + ": no polylines to render" +
                         (load.cleaned.any() ? " (" + load.cleaned.summary() + ")" : std::string()));
    load.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return load;
}

}  // namespace tc
