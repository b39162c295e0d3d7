#include "io/atomic_file.h"

#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "core/error.h"

namespace fs = std::filesystem;

namespace tc {

std::string hostName() {
    std::array<char, 256> buf{};
    if (gethostname(buf.data(), buf.size() - 1) != 0 || buf[0] == '\0') return "localhost";
    std::string host(buf.data());
    // A host name with a path separator would move the temp file elsewhere.
    for (char& c : host)
        if (c == '/') c = '_';
    return host;
}

AtomicFile::AtomicFile(std::string finalPath) : m_finalPath(std::move(finalPath)) {
    fs::path path(m_finalPath);
    std::string name = path.filename().string();
    TC_CHECK(!name.empty());
    std::string temp = "." + name + ".tmp-" + hostName() + "-" + std::to_string(getpid()) + path.extension().string();
    m_tempPath = (path.parent_path() / temp).string();
}

AtomicFile::~AtomicFile() {
    if (m_committed) return;
    std::error_code ec;
    fs::remove(m_tempPath, ec);  // may not exist if the writer failed before creating it
}

void AtomicFile::commit() {
    TC_CHECK(!m_committed);
    std::error_code ec;
    if (!fs::exists(m_tempPath, ec))
        throw OutputError(m_finalPath + ": cannot write: temporary file " + m_tempPath + " was not created");
    fs::rename(m_tempPath, m_finalPath, ec);
    if (ec) throw OutputError(m_finalPath + ": cannot write: " + ec.message());
    m_committed = true;
}

void ensureWritableDir(const std::string& dir) {
    const std::string path = dir.empty() ? std::string(".") : dir;
    std::error_code ec;
    fs::create_directories(path, ec);
    if (ec) throw OutputError(path + ": cannot create output directory: " + ec.message());
    if (!fs::is_directory(path, ec)) throw OutputError(path + ": not a directory");
    if (access(path.c_str(), W_OK | X_OK) != 0)
        throw OutputError(path + ": output directory is not writable: " + std::strerror(errno));
}

}  // namespace tc
