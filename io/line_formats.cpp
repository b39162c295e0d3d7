#include "io/line_formats.h"

#include "core/error.h"

namespace tc {

bool isNativeLineFormat(const std::string& extension) {
    return extension == ".trk" || extension == ".tck" || extension == ".obj" || extension == ".tcb";
}

LineSet readNativeLineFile(const std::string& path) {
    const std::string ext = extensionLower(path);
    FileSource source(path);
    if (ext == ".trk") return readTrk(source);
    if (ext == ".obj") return readObjLines(source);
    if (ext == ".tcb") return readTcb(source);
    if (ext == ".tck") {
        LineSet lines = readTck(source);
        for (const auto& [tsf, name] : findTsfFiles(path)) {
            std::string attribute = name;
            for (int k = 2; lines.attribute(attribute); ++k) attribute = name + "_" + std::to_string(k);
            lines.attributes.push_back({attribute, readTsf(FileSource(tsf), lines)});
        }
        return lines;
    }
    throw InputError(path + ": not a .trk, .tck, .obj or .tcb file");
}

}  // namespace tc
