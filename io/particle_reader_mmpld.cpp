// MegaMol MMPLD particle files, versions 100-103 (the layout of MegaMol's MMPLDDataSource and
// VISUS' mmpld library): little endian,
//   header  "MMPLD\0", uint16 version, uint32 frames, float bbox[6], float clipbox[6],
//           uint64 seek table[frames + 1] (byte offsets of the frames and of the file's end)
//   frame   [float timestamp (>= 102)], int32 lists, lists
//   list    uint8 vertex type, uint8 colour type, [float global radius (no per-vertex radius)],
//           [uint8 rgba global colour (colour type none) | float min, max intensity (intensity)],
//           uint64 count, [float bbox[6] (103)], count x (vertex, colour),
//           [101: uint32 cluster count, uint64 cluster bytes, the bytes]
// Every count and offset is checked against the file size before anything is read or allocated.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "core/error.h"
#include "core/particle_set.h"

namespace tc {

namespace {

class Reader {
public:
    Reader(const std::string& path, const std::string& bytes) : m_path(path), m_bytes(bytes) {}
    template <class T>
    T read(const char* what) {
        need(sizeof(T), what);
        T v;
        std::memcpy(&v, m_bytes.data() + m_pos, sizeof(T));
        m_pos += sizeof(T);
        return v;
    }
    void need(std::uint64_t n, const char* what) const {
        if (n > m_bytes.size() - m_pos)
            fail(std::string("truncated: ") + what + " needs " + std::to_string(n) + " bytes, " +
                 std::to_string(m_bytes.size() - m_pos) + " left");
    }
    void seek(std::uint64_t pos) {
        if (pos > m_bytes.size()) fail("offset " + std::to_string(pos) + " is beyond the end of the file");
        m_pos = std::size_t(pos);
    }
    void skip(std::uint64_t n, const char* what) {
        need(n, what);
        m_pos += std::size_t(n);
    }
    std::size_t pos() const { return m_pos; }
    const char* data() const { return m_bytes.data() + m_pos; }
    [[noreturn]] void fail(const std::string& message) const {
        throw InputError(m_path + ": byte " + std::to_string(m_pos) + ": " + message);
    }

private:
    const std::string& m_path;
    const std::string& m_bytes;
    std::size_t m_pos = 0;
};

// Per-vertex byte sizes by type (index = type code).
constexpr std::uint32_t kVertexSize[] = {0, 12, 16, 6, 24};
constexpr std::uint32_t kColorSize[] = {0, 3, 4, 4, 12, 16, 8, 8};

template <class T>
T load(const char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

}  // namespace

ParticleData readMmpld(const std::string& path, const std::string& bytes) {
    Reader r(path, bytes);
    r.need(6, "the magic \"MMPLD\\0\"");
    if (std::memcmp(r.data(), "MMPLD\0", 6) != 0) r.fail("not an MMPLD file (magic \"MMPLD\\0\" missing)");
    r.skip(6, "magic");
    const auto version = r.read<std::uint16_t>("version");
    if (version < 100 || version > 103) r.fail("unsupported MMPLD version " + std::to_string(version) + " (100-103)");
    const auto frames = r.read<std::uint32_t>("frame count");
    r.skip(12 * sizeof(float), "bounding and clipping boxes");
    r.need((std::uint64_t(frames) + 1) * 8, "the seek table");
    std::vector<std::uint64_t> seek(std::size_t(frames) + 1);
    for (auto& s : seek) s = r.read<std::uint64_t>("seek table");

    ParticleData data;
    for (std::uint32_t fi = 0; fi < frames; ++fi) {
        if (seek[fi] > seek[fi + 1] || seek[fi + 1] > bytes.size())
            r.fail("seek table entry " + std::to_string(fi) + " (" + std::to_string(seek[fi]) + ".." +
                   std::to_string(seek[fi + 1]) + ") is out of order or beyond the file (" +
                   std::to_string(bytes.size()) + " bytes)");
        r.seek(seek[fi]);
        if (version >= 102) r.read<float>("frame timestamp");
        const auto lists = r.read<std::int32_t>("list count");
        if (lists < 0) r.fail("negative list count " + std::to_string(lists));
        ParticleSet f;
        Attribute intensity{"intensity", {}}, list{"list", {}};
        bool anyIntensity = false;
        for (std::int32_t li = 0; li < lists; ++li) {
            const auto vtype = r.read<std::uint8_t>("vertex type");
            const auto ctype = r.read<std::uint8_t>("colour type");
            if (vtype > 4) r.fail("unknown vertex type " + std::to_string(vtype));
            if (ctype > 7) r.fail("unknown colour type " + std::to_string(ctype));
            if ((vtype == 4 || ctype == 7) && version < 103)
                r.fail("vertex type 4 / colour type 7 (double) need MMPLD version 103");
            float globalRadius = 0.5f;
            if (vtype != 2 && vtype != 0) globalRadius = r.read<float>("global radius");
            glm::vec4 globalColor(1.0f);
            float iMin = 0, iMax = 1;
            if (ctype == 0) {
                for (int c = 0; c < 4; ++c) globalColor[c] = float(r.read<std::uint8_t>("global colour")) / 255.0f;
            } else if (ctype == 3 || ctype == 7) {
                iMin = r.read<float>("intensity range");
                iMax = r.read<float>("intensity range");
            }
            const auto count = r.read<std::uint64_t>("particle count");
            if (version == 103) r.skip(6 * sizeof(float), "list bounding box");
            const std::uint64_t stride = kVertexSize[vtype] + kColorSize[ctype];
            if (vtype == 0) {  // no positions: nothing to draw; skip the colours
                if (count > (bytes.size() - r.pos()) / std::max<std::uint64_t>(stride, 1))
                    r.fail("list data truncated");
                r.skip(count * stride, "list data");
                continue;
            }
            if (count > (bytes.size() - r.pos()) / stride)
                r.fail("list " + std::to_string(li) + ": " + std::to_string(count) + " particles of " +
                       std::to_string(stride) + " bytes exceed the " + std::to_string(bytes.size() - r.pos()) +
                       " bytes left");
            const char* p = r.data();
            for (std::uint64_t i = 0; i < count; ++i, p += stride) {
                glm::vec3 pos;
                float radius = globalRadius;
                switch (vtype) {
                    case 1:
                        pos = {load<float>(p), load<float>(p + 4), load<float>(p + 8)};
                        break;
                    case 2:
                        pos = {load<float>(p), load<float>(p + 4), load<float>(p + 8)};
                        radius = load<float>(p + 12);
                        break;
                    // Short coordinates are stored as is (MegaMol scales them by the bounding box only
                    // in some data sources); the integer values become world units.
                    case 3:
                        pos = {float(load<std::int16_t>(p)), float(load<std::int16_t>(p + 2)),
                               float(load<std::int16_t>(p + 4))};
                        break;
                    default:
                        pos = {float(load<double>(p)), float(load<double>(p + 8)), float(load<double>(p + 16))};
                        break;
                }
                if (!std::isfinite(pos.x) || !std::isfinite(pos.y) || !std::isfinite(pos.z)) continue;
                const char* c = p + kVertexSize[vtype];
                glm::vec4 color = globalColor;
                float value = std::nanf("");
                switch (ctype) {
                    case 1:
                        color = glm::vec4(float(std::uint8_t(c[0])), float(std::uint8_t(c[1])),
                                          float(std::uint8_t(c[2])), 255.0f) /
                                255.0f;
                        break;
                    case 2:
                        color = glm::vec4(float(std::uint8_t(c[0])), float(std::uint8_t(c[1])),
                                          float(std::uint8_t(c[2])), float(std::uint8_t(c[3]))) /
                                255.0f;
                        break;
                    case 3:
                        value = load<float>(c);
                        break;
                    case 4:
                        color = glm::vec4(load<float>(c), load<float>(c + 4), load<float>(c + 8), 1.0f);
                        break;
                    case 5:
                        color = glm::vec4(load<float>(c), load<float>(c + 4), load<float>(c + 8), load<float>(c + 12));
                        break;
                    case 6:
                        color = glm::vec4(load<std::uint16_t>(c), load<std::uint16_t>(c + 2),
                                          load<std::uint16_t>(c + 4), load<std::uint16_t>(c + 6)) /
                                65535.0f;
                        break;
                    case 7:
                        value = float(load<double>(c));
                        break;
                    default:
                        break;
                }
                if (ctype == 3 || ctype == 7) {
                    anyIntensity = true;
                    // Intensity lists are coloured by style.color through the "intensity" attribute.
                    color = glm::vec4(1.0f);
                    (void)iMin;
                    (void)iMax;
                }
                f.positions.push_back(pos);
                f.radii.push_back(radius);
                f.colors.push_back(glm::clamp(color, glm::vec4(0.0f), glm::vec4(1.0f)));
                f.radiiFrom = f.colorsFrom = Provenance::File;
                intensity.values.push_back(value);
                list.values.push_back(float(li));
            }
            r.skip(count * stride, "list data");
            if (version == 101) {
                r.read<std::uint32_t>("cluster count");
                const auto clusterBytes = r.read<std::uint64_t>("cluster bytes");
                r.skip(clusterBytes, "cluster data");
            }
        }
        if (anyIntensity) f.attributes.push_back(std::move(intensity));
        f.attributes.push_back(std::move(list));
        f.update();
        data.frames.push_back(std::move(f));
    }
    if (data.frames.empty()) throw InputError(path + ": the MMPLD file has no frames");
    return data;
}

}  // namespace tc
