#include "core/vrc_packed.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "core/error.h"

namespace tc {

namespace {

int ceilLog2(int q) {
    int b = 0;
    while ((1 << b) < q) ++b;
    return b;
}

int channel(std::uint32_t c, int k) {
    return int((c >> (8 * k)) & 0xFFu);
}

// n <= 32 bits of `value` at bit `pos` of `bytes` (least significant bit first); the bits must be 0.
void putBits(std::uint8_t* bytes, std::size_t pos, std::uint32_t value, int n) {
    for (int k = 0; k < n;) {
        const std::size_t byte = (pos + std::size_t(k)) >> 3;
        const int shift = int((pos + std::size_t(k)) & 7u);
        const int take = std::min(8 - shift, n - k);
        bytes[byte] = std::uint8_t(bytes[byte] | (((value >> k) & ((1u << take) - 1u)) << shift));
        k += take;
    }
}

std::uint32_t getBits(const std::uint8_t* bytes, std::size_t pos, int n) {
    std::uint32_t value = 0;
    for (int k = 0; k < n;) {
        const std::size_t byte = (pos + std::size_t(k)) >> 3;
        const int shift = int((pos + std::size_t(k)) & 7u);
        const int take = std::min(8 - shift, n - k);
        value |= ((std::uint32_t(bytes[byte]) >> shift) & ((1u << take) - 1u)) << k;
        k += take;
    }
    return value;
}

// The 16-byte model's end code (face << kBinBits | bin) in the paper layout.
std::uint32_t repackEnd(const VrcPaperLayout& layout, std::uint32_t code) {
    const std::uint32_t face = code >> kBinBits, bin = code & kBinMask;
    if (face != kInteriorFace) return (face << layout.binBits) | bin;
    const std::uint32_t m = std::uint32_t(std::min(layout.quantization, kInteriorLattice));
    const std::uint32_t mp = std::uint32_t(layout.interiorLattice);
    std::uint32_t index = bin;
    if (mp != m) {
        // The model's cell centre (2 c + 1) / 2m, snapped to the m' cell holding it (exact integers).
        const std::uint32_t cell[3] = {bin % m, bin / m % m, bin / m / m};
        std::uint32_t c[3];
        for (int k = 0; k < 3; ++k) c[k] = std::min((2u * cell[k] + 1u) * mp / (2u * m), mp - 1u);
        index = (c[2] * mp + c[1]) * mp + c[0];
    }
    return ((kInteriorFace + (index >> layout.binBits)) << layout.binBits) | (index & ((1u << layout.binBits) - 1u));
}

std::uint32_t radius8(std::uint32_t r16) {
    return (r16 * 255u + 32767u) / 65535u;
}

// The local line id of each piece of voxel h (the index of its polyline among the voxel's
// distinct polylines, in order of first appearance) into local[0 .. count); returns how many
// distinct polylines the voxel holds (ids past 0xFFFF wrap: such a voxel cannot be packed anyway).
// Sorting, not a linear search per piece: dense bundles put thousands of pieces of hundreds of
// polylines in one voxel.
std::uint32_t localLineIds(const VrcModel& model, const VrcVoxel& h, std::uint16_t* local) {
    const std::uint32_t count = h.count & kCountMask;
    thread_local std::vector<std::uint64_t> byLine;  // line << 32 | position
    thread_local std::vector<std::uint32_t> firsts;
    byLine.resize(count);
    for (std::uint32_t k = 0; k < count; ++k)
        byLine[k] = (std::uint64_t(model.compact[std::size_t(h.offset) + k].line & kLineMask) << 32) | k;
    std::sort(byLine.begin(), byLine.end());
    firsts.clear();
    for (std::uint32_t k = 0; k < count; ++k)
        if (k == 0 || (byLine[k] >> 32) != (byLine[k - 1] >> 32)) firsts.push_back(std::uint32_t(byLine[k]));
    std::sort(firsts.begin(), firsts.end());
    std::uint32_t id = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
        if (k == 0 || (byLine[k] >> 32) != (byLine[k - 1] >> 32))
            id = std::uint32_t(std::lower_bound(firsts.begin(), firsts.end(), std::uint32_t(byLine[k])) -
                               firsts.begin());
        local[std::uint32_t(byLine[k])] = std::uint16_t(id);
    }
    return std::uint32_t(firsts.size());
}

}  // namespace

int vrcPaperInteriorLattice(int quantization) {
    const int binBits = 2 * ceilLog2(quantization);
    int m = std::min(quantization, kInteriorLattice);
    while (m > 1 && std::uint64_t(m) * m * m > (std::uint64_t(1) << (binBits + 1))) --m;
    return m;
}

VrcPaperLayout vrcPaperLayout(int quantization, bool copies, bool radiusVaries, int lineBits, int countBytes) {
    TC_CHECK(quantization >= 1 && quantization <= kMaxQuantization);
    TC_CHECK(lineBits >= kPaperLineBits && lineBits <= kPaperMaxLineBits);
    TC_CHECK(countBytes == 1 || countBytes == 2);
    VrcPaperLayout l;
    l.quantization = quantization;
    l.binBits = 2 * ceilLog2(quantization);
    l.endBits = 3 + l.binBits;
    l.interiorLattice = vrcPaperInteriorLattice(quantization);
    l.copies = copies;
    l.radiusVaries = radiusVaries;
    l.lineBits = lineBits;
    l.countBytes = countBytes;
    return l;
}

VrcPalette vrcPaperPalette(const std::vector<std::uint32_t>& colors) {
    VrcPalette p;
    std::vector<std::uint32_t> sorted(colors);
    tbb::parallel_sort(sorted.begin(), sorted.end());
    // Distinct colours and how often each occurs.
    std::vector<std::uint32_t> distinct;
    std::vector<std::uint64_t> weight;
    for (std::size_t i = 0; i < sorted.size();) {
        std::size_t j = i;
        while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
        distinct.push_back(sorted[i]);
        weight.push_back(j - i);
        i = j;
    }
    std::vector<std::uint8_t> entryOf(distinct.size(), 0);  // per distinct colour (in sorted order)
    if (distinct.size() <= 256) {
        p.colors = distinct;
        for (std::size_t i = 0; i < distinct.size(); ++i) entryOf[i] = std::uint8_t(i);
    } else {
        p.exact = false;
        // Median cut on a permutation of the distinct colours; boxes are ranges of it.
        std::vector<std::uint32_t> order(distinct.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = std::uint32_t(i);
        struct Box {
            std::size_t begin, end;
            int range, axis;
        };
        auto measure = [&](std::size_t begin, std::size_t end) {
            Box b{begin, end, 0, 0};
            for (int k = 0; k < 4; ++k) {
                int lo = 255, hi = 0;
                for (std::size_t i = begin; i < end; ++i) {
                    lo = std::min(lo, channel(distinct[order[i]], k));
                    hi = std::max(hi, channel(distinct[order[i]], k));
                }
                if (hi - lo > b.range) {
                    b.range = hi - lo;
                    b.axis = k;
                }
            }
            return b;
        };
        std::vector<Box> boxes{measure(0, order.size())};
        while (boxes.size() < 256) {
            std::size_t pick = boxes.size();
            for (std::size_t b = 0; b < boxes.size(); ++b)
                if (boxes[b].range > 0 && (pick == boxes.size() || boxes[b].range > boxes[pick].range)) pick = b;
            if (pick == boxes.size()) break;
            const Box box = boxes[pick];
            const int k = box.axis;
            // A total order (channel, then the whole colour): deterministic.
            std::sort(order.begin() + std::ptrdiff_t(box.begin), order.begin() + std::ptrdiff_t(box.end),
                      [&](std::uint32_t a, std::uint32_t b) {
                          const int ca = channel(distinct[a], k), cb = channel(distinct[b], k);
                          return ca != cb ? ca < cb : distinct[a] < distinct[b];
                      });
            std::uint64_t total = 0;
            for (std::size_t i = box.begin; i < box.end; ++i) total += weight[order[i]];
            std::uint64_t sum = 0;
            std::size_t split = box.begin + 1;
            for (std::size_t i = box.begin; i < box.end; ++i) {
                sum += weight[order[i]];
                if (2 * sum >= total) {
                    split = i + 1;
                    break;
                }
            }
            split = std::clamp(split, box.begin + 1, box.end - 1);
            boxes[pick] = measure(box.begin, split);
            boxes.push_back(measure(split, box.end));
        }
        for (std::size_t b = 0; b < boxes.size(); ++b) {
            double sum[4] = {0, 0, 0, 0}, w = 0;
            for (std::size_t i = boxes[b].begin; i < boxes[b].end; ++i) {
                const std::uint32_t d = order[i];
                for (int k = 0; k < 4; ++k) sum[k] += double(weight[d]) * channel(distinct[d], k);
                w += double(weight[d]);
                entryOf[d] = std::uint8_t(b);
            }
            std::uint32_t c = 0;
            for (int k = 0; k < 4; ++k) c |= std::uint32_t(std::clamp(int(sum[k] / w + 0.5), 0, 255)) << (8 * k);
            p.colors.push_back(c);
        }
    }
    for (std::size_t i = 0; i < distinct.size(); ++i)
        for (int k = 0; k < 4; ++k)
            p.maxError = std::max(p.maxError, std::abs(channel(distinct[i], k) - channel(p.colors[entryOf[i]], k)));
    p.index.resize(colors.size());
    tbb::parallel_for(std::size_t(0), colors.size(), [&](std::size_t i) {
        const auto it = std::lower_bound(distinct.begin(), distinct.end(), colors[i]);
        p.index[i] = entryOf[std::size_t(it - distinct.begin())];
    });
    return p;
}

std::vector<std::uint32_t> VrcPackedModel::words() const {
    // The bytes are little-endian bit strings; the words are read on a little-endian host (x86,
    // the GL's byte order too), so a memcpy is the conversion.
    std::vector<std::uint32_t> w((bytes.size() + 3) / 4, 0u);
    if (!bytes.empty()) std::memcpy(w.data(), bytes.data(), bytes.size());
    return w;
}

VrcPackResult packVrcModel(const VrcModel& model) {
    VrcPackResult result;
    if (model.quantization == 0) {
        result.reason = "render.vrc.quantization 0 keeps exact float end points, which have no end codes to pack";
        return result;
    }
    const std::size_t voxels = model.voxels.size();
    // The widest count and local line id any voxel needs; the voxels beyond what the layout can
    // hold: how many, and the first (lowest index: deterministic).
    std::atomic<std::size_t> badVoxel{voxels}, tooManyPieces{0}, tooManyLines{0}, widePieces{0}, wideLines{0};
    std::atomic<std::uint32_t> mostPieces{0}, mostLines{0};
    // Per piece, kept for the packing below: at most kPaperMaxLineBits bits where the model packs.
    std::vector<std::uint16_t> localIds(model.compact.size());
    auto raise = [](std::atomic<std::uint32_t>& to, std::uint32_t v) {
        std::uint32_t cur = to.load();
        while (v > cur && !to.compare_exchange_weak(cur, v)) {
        }
    };
    tbb::parallel_for(std::size_t(0), voxels, [&](std::size_t v) {
        const VrcVoxel& h = model.voxels[v];
        const std::uint32_t count = h.count & kCountMask;
        const std::uint32_t lines = count > 0 ? localLineIds(model, h, localIds.data() + h.offset) : 0u;
        bool bad = false;
        if (count > std::uint32_t(kPaperMaxPiecesPerVoxel)) ++tooManyPieces, bad = true;
        if (lines > (1u << kPaperMaxLineBits)) ++tooManyLines, bad = true;
        if (count > 255u) ++widePieces;
        if (lines > (1u << kPaperLineBits)) ++wideLines;
        raise(mostPieces, count);
        raise(mostLines, lines);
        if (bad) {
            std::size_t cur = badVoxel.load();
            while (v < cur && !badVoxel.compare_exchange_weak(cur, v)) {
            }
        }
    });
    result.tooManyPieces = tooManyPieces.load();
    result.tooManyLines = tooManyLines.load();
    result.widePieces = widePieces.load();
    result.wideLines = wideLines.load();
    if (badVoxel.load() < voxels) {
        const glm::ivec3 c = model.coords(badVoxel.load());
        result.reason = std::to_string(tooManyPieces.load()) + " voxels hold more than " +
                        std::to_string(kPaperMaxPiecesPerVoxel) + " pieces (a 2-byte count) and " +
                        std::to_string(tooManyLines.load()) + " more than " + std::to_string(1 << kPaperMaxLineBits) +
                        " distinct polylines (a " + std::to_string(kPaperMaxLineBits) +
                        "-bit local line id), the first at (" + std::to_string(c.x) + ", " + std::to_string(c.y) +
                        ", " + std::to_string(c.z) + "); a higher render.vrc.resolution (smaller voxels) may fit";
        return result;
    }
    const int lineBits = std::max(kPaperLineBits, ceilLog2(int(std::max(mostLines.load(), 1u))));
    const int countBytes = mostPieces.load() > 255u ? 2 : 1;

    const std::size_t pieces = model.compact.size();
    VrcPackedModel& p = result.model;
    p.size = model.size;
    p.origin = model.origin;
    p.voxelSize = model.voxelSize;
    p.maxRadius = model.maxRadius;
    p.pieceCount = pieces;
    bool radiusVaries = false;
    if (pieces > 0) {
        const std::uint32_t r = model.compact[0].radius & 0xFFFFu;
        p.constantRadius = r;
        const std::uint32_t both = r | (r << 16);
        for (const VrcCompactPiece& c : model.compact)
            if (c.radius != both) {
                radiusVaries = true;
                break;
            }
    }
    p.layout = vrcPaperLayout(model.quantization, model.copies > 0, radiusVaries, lineBits, countBytes);
    if (radiusVaries) p.constantRadius = 0;

    std::vector<std::uint32_t> colors(pieces);
    tbb::parallel_for(std::size_t(0), pieces, [&](std::size_t i) { colors[i] = model.compact[i].color; });
    VrcPalette palette = vrcPaperPalette(colors);
    colors = {};
    p.paletteSize = int(palette.colors.size());
    p.paletteExact = palette.exact;
    p.paletteMaxError = palette.maxError;
    p.palette.assign(256, 0u);
    std::copy(palette.colors.begin(), palette.colors.end(), p.palette.begin());

    p.offsets.resize(voxels);
    p.counts.resize(voxels);
    const std::size_t bytesPerPiece = std::size_t(p.layout.bytesPerPiece());
    // Padded to whole words plus two: the ray caster reads three words from a piece's first.
    p.bytes.assign((pieces * bytesPerPiece + 3) / 4 * 4 + 8, 0u);
    p.globalIds.resize(pieces);
    const VrcPaperLayout layout = p.layout;
    tbb::parallel_for(std::size_t(0), voxels, [&](std::size_t v) {
        const VrcVoxel& h = model.voxels[v];
        const std::uint32_t count = h.count & kCountMask;
        p.offsets[v] = count > 0 ? h.offset : 0u;
        p.counts[v] = std::uint16_t(count);
        for (std::uint32_t k = 0; k < count; ++k) {
            const std::size_t i = std::size_t(h.offset) + k;
            const VrcCompactPiece& c = model.compact[i];
            p.globalIds[i] = c.line & kLineMask;
            // Pieces start at whole bytes: no two pieces share a byte, so voxels pack in parallel.
            std::uint8_t* out = p.bytes.data() + i * bytesPerPiece;
            putBits(out, 0, repackEnd(layout, c.ends & 0xFFFFu), layout.endBits);
            putBits(out, std::size_t(layout.endBits), repackEnd(layout, c.ends >> 16), layout.endBits);
            putBits(out, std::size_t(layout.colorShift()), palette.index[i], kPaperColorBits);
            putBits(out, std::size_t(layout.lineShift()), localIds[i], layout.lineBits);
            if (layout.copies) putBits(out, std::size_t(layout.offsetShift()), c.line >> kLineBits, kPaperOffsetBits);
            if (layout.radiusVaries)
                putBits(out, std::size_t(layout.radiusShift()),
                        radius8(c.radius & 0xFFFFu) | (radius8(c.radius >> 16) << 8), kPaperRadiusBits);
        }
    });
    return result;
}

std::vector<std::uint32_t> VrcPackedModel::countWords() const {
    const std::size_t perWord = layout.countBytes == 1 ? 4 : 2;
    std::vector<std::uint32_t> w((counts.size() + perWord - 1) / perWord, 0u);
    for (std::size_t v = 0; v < counts.size(); ++v)
        w[v / perWord] |= std::uint32_t(counts[v]) << (32 / perWord * (v % perWord));
    return w;
}

VrcPaperFields vrcPaperFields(const VrcPackedModel& packed, std::size_t i) {
    const VrcPaperLayout& l = packed.layout;
    const std::uint8_t* in = packed.bytes.data() + i * std::size_t(l.bytesPerPiece());
    VrcPaperFields f{};
    f.endA = getBits(in, 0, l.endBits);
    f.endB = getBits(in, std::size_t(l.endBits), l.endBits);
    f.color = getBits(in, std::size_t(l.colorShift()), kPaperColorBits);
    f.line = getBits(in, std::size_t(l.lineShift()), l.lineBits);
    f.offset = l.copies ? getBits(in, std::size_t(l.offsetShift()), kPaperOffsetBits) : 0u;
    f.radius = l.radiusVaries ? getBits(in, std::size_t(l.radiusShift()), kPaperRadiusBits) : 0u;
    return f;
}

VrcPiece unpackVrcPiece(const VrcPackedModel& packed, std::size_t voxel, std::size_t i) {
    const VrcPaperLayout& l = packed.layout;
    const VrcPaperFields f = vrcPaperFields(packed, i);
    // The grid for decodeEnd (its geometry only).
    VrcModel grid;
    grid.size = packed.size;
    grid.origin = packed.origin;
    grid.voxelSize = packed.voxelSize;
    grid.quantization = l.quantization;
    const glm::ivec3 home = grid.coords(voxel) + decodeHomeOffset(f.offset);
    const std::uint32_t m = std::uint32_t(std::min(l.quantization, kInteriorLattice));
    auto end = [&](std::uint32_t code, bool& vertex) {
        const std::uint32_t face = code >> l.binBits, bin = code & ((1u << l.binBits) - 1u);
        vertex = face >= kInteriorFace;
        if (!vertex) return decodeEnd(grid, home, (face << kBinBits) | bin);
        const std::uint32_t index = ((face - kInteriorFace) << l.binBits) | bin;
        // The 16-byte model's lattice: its own decoder, bit for bit.
        if (std::uint32_t(l.interiorLattice) == m) return decodeEnd(grid, home, (kInteriorFace << kBinBits) | index);
        const std::uint32_t mp = std::uint32_t(l.interiorLattice);
        const glm::dvec3 cell(double(index % mp), double(index / mp % mp), double(index / mp / mp));
        return glm::vec3(glm::dvec3(packed.origin) +
                         (glm::dvec3(home) + (cell + 0.5) / double(mp)) * double(packed.voxelSize));
    };
    VrcPiece p{};
    p.a = end(f.endA, p.vertexA);
    p.b = end(f.endB, p.vertexB);
    if (l.radiusVaries) {
        p.ra = packed.maxRadius * float(f.radius & 0xFFu) / 255.0f;
        p.rb = packed.maxRadius * float(f.radius >> 8) / 255.0f;
    } else {
        p.ra = p.rb = packed.maxRadius * float(packed.constantRadius) / 65535.0f;
    }
    const std::uint32_t c = packed.palette[f.color];
    p.color = glm::vec4(float(c & 0xFFu), float((c >> 8) & 0xFFu), float((c >> 16) & 0xFFu), float(c >> 24)) / 255.0f;
    p.line = f.line;
    p.copy = f.offset != 0;
    return p;
}

float vrcPaperVertexResnapBound(const VrcPackedModel& packed) {
    const int m = std::min(packed.layout.quantization, kInteriorLattice);
    if (packed.layout.interiorLattice == m) return 0.0f;
    return 0.5f * std::sqrt(3.0f) * packed.voxelSize / float(packed.layout.interiorLattice);
}

}  // namespace tc
