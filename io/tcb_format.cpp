// tubecast's binary line format (.tcb), version 1; the layout is specified in docs/formats.md.
// Made for fast reloads: after a 40-byte header and the attribute names, the arrays are stored
// exactly as LineSet holds them, so reading is one pread per array straight into the vectors.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <set>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/line_formats.h"

namespace tc {

namespace {

constexpr char kMagic[8] = {'T', 'C', 'B', 'L', 'I', 'N', 'E', 'S'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 40;
constexpr std::uint32_t kMaxAttributes = 65535;
constexpr std::uint32_t kMaxNameBytes = 4096;

std::uint64_t padTo8(std::uint64_t n) {
    return (n + 7) & ~std::uint64_t(7);
}

}  // namespace

LineSet readTcb(const ByteSource& source) {
    std::uint8_t h[kHeaderBytes];
    if (source.size() < kHeaderBytes)
        source.failAt(source.size(), "truncated .tcb header (" + std::to_string(source.size()) + " of 40 bytes)");
    source.read(0, h, kHeaderBytes, "the header");
    if (std::memcmp(h, kMagic, 8) != 0) source.failAt(0, "not a .tcb file (no \"TCBLINES\" magic)");
    const auto version = loadLittle<std::uint32_t>(h + 8);
    if (version != kVersion)
        source.failAt(8, "unsupported .tcb version " + std::to_string(version) + " (this build reads version 1)");
    const auto attributeCount = loadLittle<std::uint32_t>(h + 12);
    const auto vertexCount = loadLittle<std::uint64_t>(h + 16);
    const auto polylineCount = loadLittle<std::uint64_t>(h + 24);
    const auto nameBytes = loadLittle<std::uint64_t>(h + 32);

    // Each count alone must fit the file before the sizes are combined (no overflow below).
    const std::uint64_t size = source.size();
    if (attributeCount > kMaxAttributes)
        source.failAt(
            12, "attribute count " + std::to_string(attributeCount) + " exceeds " + std::to_string(kMaxAttributes));
    if (vertexCount > std::numeric_limits<std::uint32_t>::max() || vertexCount > size / 12)
        source.failAt(16, "vertex count " + std::to_string(vertexCount) + " does not fit the " + std::to_string(size) +
                              "-byte file");
    if (polylineCount >= size / 4)
        source.failAt(24, "polyline count " + std::to_string(polylineCount) + " does not fit the " +
                              std::to_string(size) + "-byte file");
    if (nameBytes > size) source.failAt(32, "name table size " + std::to_string(nameBytes) + " exceeds the file");
    const std::uint64_t namesEnd = padTo8(kHeaderBytes + nameBytes);
    const std::uint64_t offsetsAt = namesEnd;
    const std::uint64_t positionsAt = offsetsAt + 4 * (polylineCount + 1);
    const std::uint64_t valuesAt = positionsAt + 12 * vertexCount;
    const std::uint64_t expected = valuesAt + 4 * std::uint64_t(attributeCount) * vertexCount;
    if (expected != size)
        source.failAt(size < expected ? size : expected,
                      "file size " + std::to_string(size) + " does not match the header (" + std::to_string(expected) +
                          " bytes for " + std::to_string(vertexCount) + " vertices, " + std::to_string(polylineCount) +
                          " polylines, " + std::to_string(attributeCount) + " attributes)" +
                          (size < expected ? ": truncated" : ""));

    LineSet lines;
    std::vector<std::uint8_t> names(nameBytes);
    source.read(kHeaderBytes, names.data(), names.size(), "the attribute names");
    std::set<std::string> seen;
    std::size_t p = 0;
    for (std::uint32_t a = 0; a < attributeCount; ++a) {
        const std::uint64_t at = kHeaderBytes + p;
        if (names.size() - p < 4) source.failAt(at, "attribute name table ends before attribute " + std::to_string(a));
        const auto length = loadLittle<std::uint32_t>(names.data() + p);
        if (length == 0 || length > kMaxNameBytes || length > names.size() - p - 4)
            source.failAt(at, "attribute " + std::to_string(a) + ": name length " + std::to_string(length) +
                                  " (expected 1.." + std::to_string(kMaxNameBytes) + " within the name table)");
        std::string name(reinterpret_cast<const char*>(names.data() + p + 4), length);
        if (!seen.insert(name).second) source.failAt(at, "attribute name \"" + name + "\" appears twice");
        lines.attributes.push_back({std::move(name), {}});
        p += 4 + length;
    }
    if (p != names.size())
        source.failAt(kHeaderBytes + p, std::to_string(names.size() - p) + " unused bytes in the attribute name table");

    lines.offsets.resize(polylineCount + 1);
    source.read(offsetsAt, lines.offsets.data(), 4 * lines.offsets.size(), "the polyline offsets");
    if (lines.offsets[0] != 0)
        source.failAt(offsetsAt, "first polyline offset is " + std::to_string(lines.offsets[0]) + ", not 0");
    for (std::size_t i = 1; i < lines.offsets.size(); ++i)
        if (lines.offsets[i] < lines.offsets[i - 1])
            source.failAt(offsetsAt + 4 * i, "polyline offsets decrease (" + std::to_string(lines.offsets[i - 1]) +
                                                 " then " + std::to_string(lines.offsets[i]) + ")");
    if (lines.offsets.back() != vertexCount)
        source.failAt(offsetsAt + 4 * polylineCount, "last polyline offset " + std::to_string(lines.offsets.back()) +
                                                         " is not the vertex count " + std::to_string(vertexCount));

    lines.positions.resize(vertexCount);
    source.read(positionsAt, lines.positions.data(), 12 * vertexCount, "the positions");
    for (std::uint32_t a = 0; a < attributeCount; ++a) {
        lines.attributes[a].values.resize(vertexCount);
        source.read(valuesAt + 4 * std::uint64_t(a) * vertexCount, lines.attributes[a].values.data(), 4 * vertexCount,
                    "attribute values");
    }
    return lines;
}

namespace {

// The .tcb bytes of `lines` in order, as (pointer, size) pieces handed to `put`, so a file and a
// memory buffer are written by the same code. `where` names the destination in errors.
template <class Put>
void emitTcb(const LineSet& lines, const std::string& where, Put&& put) {
    static_assert(sizeof(glm::vec3) == 12, "positions are written as packed float triples");
    TC_CHECK(!lines.offsets.empty());
    TC_CHECK_OP(std::size_t(lines.offsets.back()), ==, lines.positions.size());
    for (const Attribute& a : lines.attributes) TC_CHECK_OP(a.values.size(), ==, lines.positions.size());
    if (lines.attributes.size() > kMaxAttributes)
        throw OutputError(where + ": cannot write: more than " + std::to_string(kMaxAttributes) + " attributes");

    std::vector<std::uint8_t> names;
    for (const Attribute& a : lines.attributes) {
        if (a.name.empty() || a.name.size() > kMaxNameBytes)
            throw OutputError(where + ": cannot write: attribute name \"" + a.name.substr(0, 64) +
                              "\" is empty or longer than " + std::to_string(kMaxNameBytes) + " bytes");
        const auto length = std::uint32_t(a.name.size());
        names.insert(names.end(), reinterpret_cast<const std::uint8_t*>(&length),
                     reinterpret_cast<const std::uint8_t*>(&length) + 4);
        names.insert(names.end(), a.name.begin(), a.name.end());
    }
    std::uint8_t header[kHeaderBytes] = {};
    std::memcpy(header, kMagic, 8);
    const std::uint32_t version = kVersion, attributeCount = std::uint32_t(lines.attributes.size());
    const std::uint64_t vertexCount = lines.positions.size(), polylineCount = lines.polylineCount(),
                        nameBytes = names.size();
    std::memcpy(header + 8, &version, 4);
    std::memcpy(header + 12, &attributeCount, 4);
    std::memcpy(header + 16, &vertexCount, 8);
    std::memcpy(header + 24, &polylineCount, 8);
    std::memcpy(header + 32, &nameBytes, 8);
    names.resize(padTo8(kHeaderBytes + nameBytes) - kHeaderBytes, 0);

    put(header, sizeof header);
    put(names.data(), names.size());
    put(lines.offsets.data(), 4 * lines.offsets.size());
    put(lines.positions.data(), 12 * lines.positions.size());
    for (const Attribute& a : lines.attributes) put(a.values.data(), 4 * a.values.size());
}

}  // namespace

void writeTcb(const LineSet& lines, const std::string& path) {
    AtomicFile file(path);
    {
        std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(file.tempPath().c_str(), "wb"), &std::fclose);
        if (!f) throw OutputError(path + ": cannot write: " + std::strerror(errno));
        emitTcb(lines, path, [&](const void* data, std::size_t bytes) {
            if (bytes && std::fwrite(data, 1, bytes, f.get()) != bytes)
                throw OutputError(path + ": cannot write: " + std::strerror(errno));
        });
        if (std::fclose(f.release()) != 0) throw OutputError(path + ": cannot write: " + std::strerror(errno));
    }
    file.commit();
}

std::vector<std::uint8_t> encodeTcb(const LineSet& lines) {
    std::vector<std::uint8_t> bytes;
    emitTcb(lines, "(memory)", [&](const void* data, std::size_t n) {
        const auto* p = static_cast<const std::uint8_t*>(data);
        bytes.insert(bytes.end(), p, p + n);
    });
    return bytes;
}

}  // namespace tc
