#pragma once
// Bounds-checked random access to the bytes of an input file (or of a memory buffer, for the
// fuzz targets), shared by the binary line-format readers (.trk, .tck/.tsf, .obj, .tcb).
//
// Every read is checked against the real size of the source, so a reader can never be made to
// read past the end or to allocate from a size field it has not checked; errors are InputErrors
// that name the source and the byte offset: "tracks.trk: byte 1004: ...".
// Problems a reader tolerates are kept as warnings with the same kind of position.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace tc {

class ByteSource {
public:
    virtual ~ByteSource() = default;

    // The file name used in error messages.
    const std::string& name() const { return m_name; }
    std::uint64_t size() const { return m_size; }

    // Copies [offset, offset + n) into `dst`. Throws InputError "NAME: byte OFFSET: unexpected
    // end of file reading WHAT (need N bytes, M left)" when the range is not inside the source.
    void read(std::uint64_t offset, void* dst, std::size_t n, const char* what) const;

    // All bytes from `offset` to the end (one bulk read).
    std::vector<std::uint8_t> readRest(std::uint64_t offset, const char* what) const;

    // Throws InputError "NAME: byte OFFSET: MESSAGE".
    [[noreturn]] void failAt(std::uint64_t offset, const std::string& message) const;
    // Throws InputError "NAME: line LINE: MESSAGE" (text formats).
    [[noreturn]] void failAtLine(std::size_t line, const std::string& message) const;
    // Throws InputError "NAME: MESSAGE".
    [[noreturn]] void fail(const std::string& message) const;

    // Non-fatal problems the reader tolerated (a stale track count, a missing end marker), each
    // naming its position like the errors above but without the name: "byte OFFSET: MESSAGE",
    // "line LINE: MESSAGE". They collect in warnings(), in the order found, for the caller to
    // report (readLineSet puts them into CleanReport::warnings). Readers take the source by
    // const reference: the list is the one thing they add to.
    void warnAt(std::uint64_t offset, const std::string& message) const;
    void warnAtLine(std::size_t line, const std::string& message) const;
    const std::vector<std::string>& warnings() const { return m_warnings; }

    // Rejects outputs out of proportion to the input before they are allocated: a reader that
    // expands data (per-track properties copied to every vertex, .obj indices referencing the
    // same vertex many times) passes the bytes it is about to allocate. The limit is
    // 128 x the source size + 256 MiB, far above what any real file of these formats expands
    // to; beyond it the file is treated as malformed ("allocation bomb").
    void checkExpansion(std::uint64_t outputBytes, std::uint64_t offset, const char* what) const;

protected:
    ByteSource(std::string name, std::uint64_t size) : m_name(std::move(name)), m_size(size) {}
    virtual void readRaw(std::uint64_t offset, void* dst, std::size_t n) const = 0;
    void setSize(std::uint64_t size) { m_size = size; }  // FileSource knows it after opening

private:
    std::string m_name;
    std::uint64_t m_size;
    mutable std::vector<std::string> m_warnings;
};

// A file opened for reading (pread, no buffering: the readers read large ranges at once).
// Throws InputError "PATH: no such file", "PATH: is a directory" or "PATH: cannot open: REASON".
class FileSource final : public ByteSource {
public:
    explicit FileSource(const std::string& path);
    ~FileSource() override;
    FileSource(const FileSource&) = delete;
    FileSource& operator=(const FileSource&) = delete;

private:
    void readRaw(std::uint64_t offset, void* dst, std::size_t n) const override;
    void readRange(std::uint64_t offset, void* dst, std::size_t n) const;  // one pread loop
    int m_fd = -1;
};

// A caller-owned buffer (fuzz targets, tests). `name` stands in for the file name.
class MemorySource final : public ByteSource {
public:
    MemorySource(std::string name, const void* data, std::size_t size)
        : ByteSource(std::move(name), size), m_data(static_cast<const std::uint8_t*>(data)) {}

private:
    void readRaw(std::uint64_t offset, void* dst, std::size_t n) const override {
        std::memcpy(dst, m_data + offset, n);
    }
    const std::uint8_t* m_data;
};

// Little/big-endian loads from unaligned bytes.
template <class T>
T loadLittle(const std::uint8_t* p) {
    static_assert(std::endian::native == std::endian::little, "tubecast's readers assume a little-endian host");
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

inline std::uint16_t byteSwap(std::uint16_t v) {
    return __builtin_bswap16(v);
}
inline std::uint32_t byteSwap(std::uint32_t v) {
    return __builtin_bswap32(v);
}
inline std::uint64_t byteSwap(std::uint64_t v) {
    return __builtin_bswap64(v);
}

// Reverses the byte order of every `width`-byte word (2, 4 or 8) of `data` in place.
void byteSwapWords(void* data, std::size_t bytes, std::size_t width);

// Lower-cased extension with the dot: "/a/b.TRK" -> ".trk".
std::string extensionLower(const std::string& path);

// Makes attribute names unique: a repeated "fa" becomes "fa_2", "fa_3", ...
void makeNamesUnique(std::vector<std::string>& names);

}  // namespace tc
