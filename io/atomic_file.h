#pragma once
// Write-to-temp-then-rename, so a killed run never leaves a half-written output behind and a
// failed write leaves the previous file untouched.
#include <string>

namespace tc {

// This machine's host name with any '/' replaced by '_' (usable in file names), "localhost" if
// it has none. Temp files, placeholders and run.json carry it.
std::string hostName();

// Owns a temporary file next to `finalPath`: `.<name>.tmp-<host>-<pid><ext>`, e.g.
// `out/.frame.0001.png.tmp-node7-4242.png`. The temp keeps the final extension at the end so
// writers that pick a format from the file name (OpenImageIO, VTK) pick the right one; host and
// pid keep concurrent runs on a shared file system apart. Callers write to tempPath(), then
// commit() renames it over finalPath (atomic on POSIX within one file system; no fsync). If
// commit() is never reached (an exception), the destructor removes the temp file.
class AtomicFile {
public:
    explicit AtomicFile(std::string finalPath);
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;
    ~AtomicFile();

    const std::string& finalPath() const { return m_finalPath; }
    const std::string& tempPath() const { return m_tempPath; }
    bool committed() const { return m_committed; }

    // Renames the temp file to the final path. Throws OutputError "FINAL: cannot write: ..."
    // when the temp file is missing or the rename fails.
    void commit();

private:
    std::string m_finalPath;
    std::string m_tempPath;
    bool m_committed = false;
};

// Creates `dir` and its parents if needed and checks that files can be created in it.
// Throws OutputError "DIR: cannot create output directory: <reason>", "DIR: not a directory"
// or "DIR: output directory is not writable". An empty string means the current directory.
void ensureWritableDir(const std::string& dir);

}  // namespace tc
