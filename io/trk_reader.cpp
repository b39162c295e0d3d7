// TrackVis .trk reader (http://trackvis.org/docs/?subsect=fileformat). The header is a fixed
// 1000-byte C struct; nibabel's trk.py is the reference for the parts TrackVis' page leaves
// open (names encoding a value count, the voxmm -> RAS mapping) and for what is valid: what it
// reads with a warning or silently (version 3, an n_count that disagrees with the tracks, odd
// name value counts) is read here with a warning (ByteSource::warnings).
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.h"
#include "io/line_formats.h"

namespace tc {

namespace {

constexpr std::size_t kHeaderSize = 1000;
// Byte offsets of the header fields used.
constexpr std::size_t kVoxelSize = 12, kNScalars = 36, kScalarNames = 38, kNProperties = 238, kPropertyNames = 240,
                      kVoxToRas = 440, kNCount = 988, kVersion = 992, kHdrSize = 996;
constexpr std::size_t kNameBytes = 20, kNameSlots = 10;
// More values per point or track than any tool writes; a larger count is a corrupt header.
constexpr int kMaxValues = 255;

// The raw header bytes, read in the file's byte order.
struct HeaderBytes {
    const std::uint8_t* bytes;
    bool bigEndian;

    template <class T>
    T get(std::size_t offset) const {
        T v = loadLittle<T>(bytes + offset);
        if (!bigEndian) return v;
        if constexpr (sizeof(T) == 2) {
            std::uint16_t u;
            std::memcpy(&u, &v, 2);
            u = byteSwap(u);
            std::memcpy(&v, &u, 2);
        } else {
            std::uint32_t u;
            std::memcpy(&u, &v, 4);
            u = byteSwap(u);
            std::memcpy(&v, &u, 4);
        }
        return v;
    }
};

// The 10 name slots of scalars or properties -> one name per value. nibabel encodes "name, k
// values" as "name\0k" in a slot; plain names cover one value; values beyond the named ones
// are called PREFIX_i. As in nibabel's TrkFile.load, a slot of 0 values is skipped and a name
// covering more values than are left gets the ones left (both with a warning).
std::vector<std::string> valueNames(const ByteSource& source, const std::uint8_t* slots, std::size_t slotsOffset,
                                    int count, const char* prefix) {
    std::vector<std::string> names;
    for (std::size_t s = 0; s < kNameSlots && int(names.size()) < count; ++s) {
        const char* slot = reinterpret_cast<const char*>(slots + s * kNameBytes);
        const std::uint64_t at = slotsOffset + s * kNameBytes;
        std::size_t len = strnlen(slot, kNameBytes);
        std::string name(slot, len);
        if (name.empty()) break;
        int k = 1;
        // "name\0digits": the value count (nibabel's encode_value_in_name).
        if (len + 1 < kNameBytes && slot[len + 1] != '\0') {
            std::string digits(slot + len + 1, strnlen(slot + len + 1, kNameBytes - len - 1));
            k = 0;
            for (char c : digits) {
                if (c < '0' || c > '9' || k > kMaxValues)
                    source.failAt(at, "name \"" + name + "\": malformed value count after the name");
                k = 10 * k + (c - '0');
            }
            if (k < 1) {
                source.warnAt(at, "name \"" + name + "\": value count 0; the name is skipped");
                continue;
            }
        }
        const int declared = k, left = count - int(names.size());
        if (k > left) {
            source.warnAt(at, "name \"" + name + "\" covers " + std::to_string(k) + " values, more than the " +
                                  std::to_string(count) + " declared; it names the " + std::to_string(left) + " left");
            k = left;
        }
        if (declared == 1) {
            names.push_back(name);
        } else {
            for (int i = 0; i < k; ++i) names.push_back(name + "_" + std::to_string(i));
        }
    }
    while (int(names.size()) < count) names.push_back(std::string(prefix) + "_" + std::to_string(names.size()));
    return names;
}

// What the reader takes from the header.
struct TrkHeader {
    bool bigEndian = false;
    std::int32_t version = 0;
    int nScalars = 0, nProperties = 0;
    std::int32_t nCount = 0;
    std::vector<std::string> names;  // one per scalar, then one per property; unique
    // voxmm -> RAS mm (version 2 with a matrix; nibabel treats vox_to_ras[3][3] == 0 as unset).
    bool toRas = false;
    glm::vec3 voxelSize{1.0f};
    float voxToRas[4][4] = {};
};

// vox_to_ras and the voxel sizes of a version 2 header, checked when the mapping is used.
void readVoxToRas(const ByteSource& source, const HeaderBytes& h, TrkHeader& header) {
    float(&m)[4][4] = header.voxToRas;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[r][c] = h.get<float>(kVoxToRas + 4 * (4 * r + c));
    header.toRas = m[3][3] != 0.0f;
    if (!header.toRas) return;
    for (int i = 0; i < 16; ++i)
        if (!std::isfinite(m[i / 4][i % 4])) source.failAt(kVoxToRas + 4 * i, "vox_to_ras is not finite");
    for (int i = 0; i < 3; ++i) {
        float& size = header.voxelSize[i];
        size = h.get<float>(kVoxelSize + 4 * i);
        if (!(size > 0.0f) || !std::isfinite(size))
            source.failAt(kVoxelSize + 4 * i, "voxel_size[" + std::to_string(i) + "] is " + std::to_string(size) +
                                                  ", the vox_to_ras mapping needs positive sizes");
    }
}

TrkHeader readTrkHeader(const ByteSource& source) {
    if (source.size() < kHeaderSize)
        source.failAt(source.size(), "truncated TrackVis header: the file has " + std::to_string(source.size()) +
                                         " bytes, the header needs 1000");
    std::array<std::uint8_t, kHeaderSize> raw;
    source.read(0, raw.data(), raw.size(), "the header");
    if (std::memcmp(raw.data(), "TRACK", 5) != 0) source.failAt(0, "not a TrackVis file (no \"TRACK\" magic)");

    // hdr_size is 1000 in the writer's byte order: the only endianness marker the format has.
    TrkHeader header;
    HeaderBytes h{raw.data(), false};
    const std::int32_t hdrSize = h.get<std::int32_t>(kHdrSize);
    if (hdrSize != 1000) {
        h.bigEndian = true;
        if (h.get<std::int32_t>(kHdrSize) != 1000)
            source.failAt(kHdrSize, "hdr_size is " + std::to_string(hdrSize) + ", expected 1000 (either byte order)");
    }
    header.bigEndian = h.bigEndian;
    header.version = h.get<std::int32_t>(kVersion);
    if (header.version == 3) {
        // nibabel's TrkFile._read_header parses version 3 as version 2, with a warning.
        source.warnAt(kVersion, "version 3 is read as version 2");
        header.version = 2;
    }
    if (header.version != 1 && header.version != 2)
        source.failAt(kVersion, "unsupported version " + std::to_string(header.version) + " (1, 2 and 3 are)");
    header.nScalars = h.get<std::int16_t>(kNScalars);
    header.nProperties = h.get<std::int16_t>(kNProperties);
    if (header.nScalars < 0 || header.nScalars > kMaxValues)
        source.failAt(kNScalars, "n_scalars is " + std::to_string(header.nScalars) + ", expected 0.." +
                                     std::to_string(kMaxValues));
    if (header.nProperties < 0 || header.nProperties > kMaxValues)
        source.failAt(kNProperties, "n_properties is " + std::to_string(header.nProperties) + ", expected 0.." +
                                        std::to_string(kMaxValues));
    header.nCount = h.get<std::int32_t>(kNCount);
    if (header.nCount < 0) source.failAt(kNCount, "n_count is " + std::to_string(header.nCount));

    header.names = valueNames(source, raw.data() + kScalarNames, kScalarNames, header.nScalars, "scalar");
    std::vector<std::string> propertyNames =
        valueNames(source, raw.data() + kPropertyNames, kPropertyNames, header.nProperties, "property");
    header.names.insert(header.names.end(), propertyNames.begin(), propertyNames.end());
    makeNamesUnique(header.names);
    if (header.version == 2) readVoxToRas(source, h, header);
    return header;
}

struct TrackScan {
    std::uint64_t vertices = 0, tracks = 0;
};

// Pass 1: walks the tracks of `data` (the bytes after the header, in native byte order), checking
// every point count against the bytes left, so nothing is allocated from an unchecked count.
// n_count tracks are read, or all to the end of the file when it is 0, as in TrackVis and
// nibabel's TrkFile._read; like nibabel, a file that ends (between tracks) before n_count tracks
// gives the tracks it has, and bytes after n_count tracks are ignored, each with a warning. A
// track cut short is an error.
TrackScan scanTracks(const ByteSource& source, const std::vector<std::uint8_t>& data, const TrkHeader& header) {
    const std::size_t perPoint = 3 + std::size_t(header.nScalars);
    const std::int32_t nCount = header.nCount;
    TrackScan scan;
    std::size_t pos = 0;
    while (nCount == 0 ? pos < data.size() : scan.tracks < std::uint64_t(nCount)) {
        const std::uint64_t at = kHeaderSize + pos;
        if (pos == data.size()) {
            source.warnAt(at, "file ends after " + std::to_string(scan.tracks) + " of the n_count " +
                                  std::to_string(nCount) + " tracks; read " + std::to_string(scan.tracks));
            break;
        }
        if (data.size() - pos < 4)
            source.failAt(at, "truncated: track " + std::to_string(scan.tracks) + " has no complete point count");
        const std::int32_t n = loadLittle<std::int32_t>(data.data() + pos);
        if (n < 0)
            source.failAt(at, "track " + std::to_string(scan.tracks) + ": negative point count " + std::to_string(n));
        const std::uint64_t bytes = 4 * (std::uint64_t(n) * perPoint + std::uint64_t(header.nProperties));
        if (bytes > data.size() - pos - 4)
            source.failAt(at, "track " + std::to_string(scan.tracks) + " declares " + std::to_string(n) + " points (" +
                                  std::to_string(bytes) + " bytes) but only " + std::to_string(data.size() - pos - 4) +
                                  " bytes are left");
        pos += 4 + bytes;
        scan.vertices += std::uint64_t(n);
        ++scan.tracks;
    }
    if (pos != data.size())
        source.warnAt(kHeaderSize + pos, std::to_string(data.size() - pos) + " bytes after the last of the n_count " +
                                             std::to_string(nCount) + " tracks (n_count wrong?); ignored");
    return scan;
}

// Pass 2: the scanned tracks into a LineSet (positions mapped to RAS when the header says so).
LineSet fillTracks(const std::vector<std::uint8_t>& data, const TrkHeader& header, const TrackScan& scan) {
    const std::size_t perPoint = 3 + std::size_t(header.nScalars);
    const int nScalars = header.nScalars, nProperties = header.nProperties;
    const float(&m)[4][4] = header.voxToRas;
    LineSet lines;
    lines.positions.resize(scan.vertices);
    lines.offsets.reserve(scan.tracks + 1);
    lines.attributes.resize(header.names.size());
    for (std::size_t a = 0; a < header.names.size(); ++a) {
        lines.attributes[a].name = header.names[a];
        lines.attributes[a].values.resize(scan.vertices);
    }
    std::size_t v = 0, pos = 0;
    for (std::uint64_t t = 0; t < scan.tracks; ++t) {
        const auto n = std::size_t(loadLittle<std::int32_t>(data.data() + pos));
        const std::uint8_t* p = data.data() + pos + 4;
        for (std::size_t i = 0; i < n; ++i, ++v) {
            glm::vec3 q(loadLittle<float>(p), loadLittle<float>(p + 4), loadLittle<float>(p + 8));
            if (header.toRas) {
                q = q / header.voxelSize - 0.5f;
                q = glm::vec3(m[0][0] * q.x + m[0][1] * q.y + m[0][2] * q.z + m[0][3],
                              m[1][0] * q.x + m[1][1] * q.y + m[1][2] * q.z + m[1][3],
                              m[2][0] * q.x + m[2][1] * q.y + m[2][2] * q.z + m[2][3]);
            }
            lines.positions[v] = q;
            for (int s = 0; s < nScalars; ++s) lines.attributes[s].values[v] = loadLittle<float>(p + 12 + 4 * s);
            p += 4 * perPoint;
        }
        for (int k = 0; k < nProperties; ++k) {
            const float value = loadLittle<float>(p + 4 * k);
            std::vector<float>& values = lines.attributes[nScalars + k].values;
            std::fill(values.begin() + std::ptrdiff_t(v - n), values.begin() + std::ptrdiff_t(v), value);
        }
        pos += 4 + 4 * (n * perPoint + std::size_t(nProperties));
        lines.offsets.push_back(std::uint32_t(v));
    }
    return lines;
}

}  // namespace

LineSet readTrk(const ByteSource& source) {
    const TrkHeader header = readTrkHeader(source);
    // Every field after the header is a 4-byte word (int32 point counts, float32 values): one
    // bulk read, one in-place swap for big-endian files.
    std::vector<std::uint8_t> data = source.readRest(kHeaderSize, "the tracks");
    if (header.bigEndian) byteSwapWords(data.data(), data.size() - data.size() % 4, 4);
    const TrackScan scan = scanTracks(source, data, header);
    if (scan.vertices > std::numeric_limits<std::uint32_t>::max())
        source.fail("more than 2^32 - 1 vertices are not supported");
    source.checkExpansion(scan.vertices * (12 + 4 * header.names.size()) + 4 * scan.tracks, kHeaderSize, "the tracks");
    return fillTracks(data, header, scan);
}

}  // namespace tc
