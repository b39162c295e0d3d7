#include "io/byte_source.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <filesystem>
#include <set>

#include "core/error.h"

namespace tc {

void ByteSource::read(std::uint64_t offset, void* dst, std::size_t n, const char* what) const {
    if (offset > m_size || n > m_size - offset)
        failAt(offset, std::string("unexpected end of file reading ") + what + " (need " + std::to_string(n) +
                           " bytes, " + std::to_string(offset > m_size ? 0 : m_size - offset) + " left)");
    if (n) readRaw(offset, dst, n);
}

std::vector<std::uint8_t> ByteSource::readRest(std::uint64_t offset, const char* what) const {
    if (offset > m_size) failAt(offset, std::string("offset of ") + what + " is past the end of the file");
    std::vector<std::uint8_t> bytes(m_size - offset);
    read(offset, bytes.data(), bytes.size(), what);
    return bytes;
}

void ByteSource::failAt(std::uint64_t offset, const std::string& message) const {
    throw InputError(m_name + ": byte " + std::to_string(offset) + ": " + message);
}

void ByteSource::failAtLine(std::size_t line, const std::string& message) const {
    throw InputError(m_name + ": line " + std::to_string(line) + ": " + message);
}

void ByteSource::fail(const std::string& message) const {
    throw InputError(m_name + ": " + message);
}

void ByteSource::warnAt(std::uint64_t offset, const std::string& message) const {
    m_warnings.push_back("byte " + std::to_string(offset) + ": " + message);
}

void ByteSource::warnAtLine(std::size_t line, const std::string& message) const {
    m_warnings.push_back("line " + std::to_string(line) + ": " + message);
}

void ByteSource::checkExpansion(std::uint64_t outputBytes, std::uint64_t offset, const char* what) const {
    const std::uint64_t limit = 128 * m_size + (std::uint64_t(256) << 20);
    if (outputBytes > limit)
        failAt(offset, std::string(what) + " would need " + std::to_string(outputBytes) +
                           " bytes, more than 128x the " + std::to_string(m_size) + "-byte file (malformed counts?)");
}

FileSource::FileSource(const std::string& path) : ByteSource(path, 0) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
    if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory");
    m_fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (m_fd < 0) throw InputError(path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(m_fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(m_fd);
        throw InputError(path + ": not a regular file");
    }
    setSize(std::uint64_t(st.st_size));
}

FileSource::~FileSource() {
    if (m_fd >= 0) ::close(m_fd);
}

void FileSource::readRaw(std::uint64_t offset, void* dst, std::size_t n) const {
    // Large reads (the arrays of a .tcb, 10^7 vertices = 120 MB of positions) go in parallel
    // chunks: one thread copying out of the page cache (and faulting in the destination pages)
    // is slower than the disk, two keep the load I/O bound (docs/performance.md, "Batch throughput
    // and reading").
    constexpr std::size_t kChunk = std::size_t(8) << 20;
    if (n >= 2 * kChunk) {
        tbb::parallel_for(std::size_t(0), (n + kChunk - 1) / kChunk, [&](std::size_t c) {
            const std::size_t begin = c * kChunk;
            readRange(offset + begin, static_cast<char*>(dst) + begin, std::min(kChunk, n - begin));
        });
        return;
    }
    readRange(offset, dst, n);
}

void FileSource::readRange(std::uint64_t offset, void* dst, std::size_t n) const {
    auto* out = static_cast<char*>(dst);
    while (n > 0) {
        // pread moves at most ~2 GiB per call on Linux; loop for partial reads and EINTR.
        ssize_t got = ::pread(m_fd, out, n, off_t(offset));
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) failAt(offset, std::string("read error: ") + std::strerror(errno));
        if (got == 0) failAt(offset, "file shrank while being read");
        out += got;
        offset += std::uint64_t(got);
        n -= std::size_t(got);
    }
}

void byteSwapWords(void* data, std::size_t bytes, std::size_t width) {
    auto* p = static_cast<std::uint8_t*>(data);
    const std::size_t n = bytes / width;
    switch (width) {
        case 2:
            for (std::size_t i = 0; i < n; ++i) {
                std::uint16_t v;
                std::memcpy(&v, p + 2 * i, 2);
                v = byteSwap(v);
                std::memcpy(p + 2 * i, &v, 2);
            }
            break;
        case 4:
            for (std::size_t i = 0; i < n; ++i) {
                std::uint32_t v;
                std::memcpy(&v, p + 4 * i, 4);
                v = byteSwap(v);
                std::memcpy(p + 4 * i, &v, 4);
            }
            break;
        case 8:
            for (std::size_t i = 0; i < n; ++i) {
                std::uint64_t v;
                std::memcpy(&v, p + 8 * i, 8);
                v = byteSwap(v);
                std::memcpy(p + 8 * i, &v, 8);
            }
            break;
        default:
            TC_CHECK(false);
    }
}

std::string extensionLower(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

void makeNamesUnique(std::vector<std::string>& names) {
    std::set<std::string> seen;
    for (std::string& name : names) {
        if (seen.insert(name).second) continue;
        for (int k = 2;; ++k) {
            std::string candidate = name + "_" + std::to_string(k);
            if (seen.insert(candidate).second) {
                name = candidate;
                break;
            }
        }
    }
}

}  // namespace tc
