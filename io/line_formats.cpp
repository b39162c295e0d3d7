#include "io/line_formats.h"

#include "core/error.h"

namespace tc {

bool isNativeLineFormat(const std::string& extension) {
    return extension == ".trk" || extension == ".tck" || extension == ".obj" || extension == ".tcb";
}

LineSet readNativeLineFile(const std::string& path, std::vector<std::string>* warnings) {
    const std::string ext = extensionLower(path);
    FileSource source(path);
    LineSet lines;
    if (ext == ".trk") {
        lines = readTrk(source);
    } else if (ext == ".obj") {
        lines = readObjLines(source);
    } else if (ext == ".tcb") {
        lines = readTcb(source);
    } else if (ext == ".tck") {
        lines = readTck(source);
        for (const auto& [tsf, name] : findTsfFiles(path)) {
            std::string attribute = name;
            for (int k = 2; lines.attribute(attribute); ++k) attribute = name + "_" + std::to_string(k);
            const FileSource tsfSource(tsf);
            lines.attributes.push_back({attribute, readTsf(tsfSource, lines)});
            if (warnings)
                for (const std::string& w : tsfSource.warnings()) warnings->push_back(tsf + ": " + w);
        }
    } else {
        throw InputError(path + ": not a .trk, .tck, .obj or .tcb file");
    }
    if (warnings) warnings->insert(warnings->begin(), source.warnings().begin(), source.warnings().end());
    return lines;
}

}  // namespace tc
