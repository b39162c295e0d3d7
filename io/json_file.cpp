#include "io/json_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"

namespace tc {

TextPosition textPosition(const std::string& text, std::size_t offset) {
    TextPosition pos;
    std::size_t end = std::min(offset, text.size());
    std::size_t lineStart = 0;
    for (std::size_t i = 0; i < end; ++i) {
        if (text[i] == '\n') {
            ++pos.line;
            lineStart = i + 1;
        }
    }
    pos.column = offset - lineStart + 1;
    return pos;
}

namespace {

// "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error ..." ->
// "syntax error ...": the file position is printed in our own "PATH:LINE:COL" form instead.
std::string parserMessage(const std::string& what) {
    std::size_t at = what.find("parse error");
    if (at != std::string::npos) {
        std::size_t colon = what.find(": ", at);
        if (colon != std::string::npos) return what.substr(colon + 2);
    }
    return what;
}

}  // namespace

nlohmann::json readJsonFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot read: " + std::strerror(errno));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw InputError(path + ": cannot read: " + std::strerror(errno));
    const std::string text = buffer.str();
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        // e.byte is the 1-based index of the last character read, i.e. where parsing failed.
        TextPosition pos = textPosition(text, e.byte > 0 ? e.byte - 1 : 0);
        throw InputError(path + ":" + std::to_string(pos.line) + ":" + std::to_string(pos.column) + ": " +
                         parserMessage(e.what()));
    }
}

void writeJsonFile(const std::string& path, const nlohmann::json& value) {
    AtomicFile file(path);
    {
        std::ofstream out(file.tempPath(), std::ios::binary | std::ios::trunc);
        if (!out) throw OutputError(path + ": cannot write: " + std::strerror(errno));
        out << value.dump(2) << '\n';
        out.close();
        if (!out) throw OutputError(path + ": cannot write: " + std::strerror(errno));
    }
    file.commit();
}

}  // namespace tc
