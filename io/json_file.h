#pragma once
// JSON files with errors that name the file, line and column.
#include <nlohmann/json.hpp>
#include <string>

namespace tc {

// Parses a JSON file (strict: no comments, no trailing commas). Throws InputError
// "PATH: no such file", "PATH: cannot read: <reason>" or "PATH:LINE:COL: <parser message>"
// (1-based line and column of the character where parsing failed).
nlohmann::json readJsonFile(const std::string& path);

// Writes `value` pretty-printed (2-space indent, trailing newline) through an AtomicFile.
// Throws OutputError "PATH: cannot write: <reason>".
void writeJsonFile(const std::string& path, const nlohmann::json& value);

// The 1-based line and column of byte `offset` of `text` (columns count bytes).
struct TextPosition {
    std::size_t line = 1, column = 1;
};
TextPosition textPosition(const std::string& text, std::size_t offset);

}  // namespace tc
