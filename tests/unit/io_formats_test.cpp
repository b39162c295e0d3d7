// Readers of the non-VTK line formats (io/line_formats.h): hand-built .trk (LE and BE, scalars,
// properties, vox_to_ras), .tck (LE, BE, Float64) with .tsf, .obj as LineVis writes it, .tcb
// round trips; and malformed variants of each, which must throw InputError naming the file and
// the byte offset or line. Uses no VTK, so the sanitizer build (tests/fuzz/) runs it too.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/line_set.h"
#include "io/line_formats.h"
#include "test_tmp.h"

namespace fs = std::filesystem;

namespace tc {
namespace {

using tc::test::testDir;
using Bytes = std::vector<std::uint8_t>;

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// Appends numbers in either byte order.
struct Writer {
    Bytes bytes;
    bool big = false;

    template <class T>
    void put(T v) {
        std::uint8_t b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (big) std::reverse(b, b + sizeof(T));
        bytes.insert(bytes.end(), b, b + sizeof(T));
    }
    template <class T>
    void putAt(std::size_t offset, T v) {
        std::uint8_t b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (big) std::reverse(b, b + sizeof(T));
        std::memcpy(bytes.data() + offset, b, sizeof(T));
    }
    void text(const std::string& s) { bytes.insert(bytes.end(), s.begin(), s.end()); }
};

void writeFile(const std::string& path, const Bytes& bytes) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Runs `f`, expects an InputError and returns its message.
template <class F>
std::string inputErrorOf(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError thrown";
    return {};
}

#define EXPECT_CONTAINS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

template <class Reader>
std::string errorOf(Reader reader, const Bytes& bytes, const char* name = "bad.bin") {
    return inputErrorOf([&] {
        MemorySource source(name, bytes.data(), bytes.size());
        reader(source);
    });
}

// ---- .trk -----------------------------------------------------------------------------------

struct TrkTrack {
    std::vector<glm::vec3> points;
    std::vector<std::vector<float>> scalars;  // per point
    std::vector<float> properties;
};

// A TrackVis file with 2 scalars ("fa", and "rgb" covering 3 values in nibabel's encoding, so 4
// values per point) and 2 properties ("len", unnamed).
Bytes makeTrk(bool big, int version, const std::vector<TrkTrack>& tracks, int nCount = -1) {
    Writer w;
    w.big = big;
    w.bytes.assign(1000, 0);
    std::memcpy(w.bytes.data(), "TRACK", 6);
    w.putAt<std::int16_t>(6, 10);
    w.putAt<std::int16_t>(8, 10);
    w.putAt<std::int16_t>(10, 10);
    for (int i = 0; i < 3; ++i) w.putAt<float>(12 + 4 * i, 2.0f);  // voxel size
    w.putAt<std::int16_t>(36, 4);                                  // n_scalars
    std::memcpy(w.bytes.data() + 38, "fa", 2);
    std::memcpy(w.bytes.data() + 58,
                "rgb\0"
                "3",
                5);
    w.putAt<std::int16_t>(238, 2);  // n_properties
    std::memcpy(w.bytes.data() + 240, "len", 3);
    // vox_to_ras: scale 2, translation (10, 20, 30).
    const float m[16] = {2, 0, 0, 10, 0, 2, 0, 20, 0, 0, 2, 30, 0, 0, 0, 1};
    for (int i = 0; i < 16; ++i) w.putAt<float>(440 + 4 * i, m[i]);
    std::memcpy(w.bytes.data() + 948, "LPS", 3);
    w.putAt<std::int32_t>(988, nCount < 0 ? std::int32_t(tracks.size()) : nCount);
    w.putAt<std::int32_t>(992, version);
    w.putAt<std::int32_t>(996, 1000);
    for (const TrkTrack& t : tracks) {
        w.put<std::int32_t>(std::int32_t(t.points.size()));
        for (std::size_t i = 0; i < t.points.size(); ++i) {
            w.put(t.points[i].x);
            w.put(t.points[i].y);
            w.put(t.points[i].z);
            for (float s : t.scalars[i]) w.put(s);
        }
        for (float p : t.properties) w.put(p);
    }
    return w.bytes;
}

std::vector<TrkTrack> sampleTracks() {
    return {{{{1, 2, 3}, {3, 2, 1}, {5, 5, 5}}, {{0.1f, 1, 2, 3}, {0.2f, 4, 5, 6}, {0.3f, 7, 8, 9}}, {42.0f, -1.0f}},
            {{{0, 0, 0}, {2, 0, 0}}, {{0.5f, 0, 0, 0}, {0.6f, 1, 1, 1}}, {7.0f, -2.0f}}};
}

void expectSampleTrk(const LineSet& lines, bool ras) {
    ASSERT_EQ(lines.polylineCount(), 2u);
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 3, 5}));
    // ras: p_ras = M (p / 2 - 0.5) = p - 1 + (10, 20, 30).
    const glm::vec3 shift = ras ? glm::vec3(9, 19, 29) : glm::vec3(0);
    EXPECT_EQ(lines.positions[0], glm::vec3(1, 2, 3) + shift);
    EXPECT_EQ(lines.positions[2], glm::vec3(5, 5, 5) + shift);
    EXPECT_EQ(lines.positions[4], glm::vec3(2, 0, 0) + shift);
    std::vector<std::string> names;
    for (const Attribute& a : lines.attributes) names.push_back(a.name);
    EXPECT_EQ(names, (std::vector<std::string>{"fa", "rgb_0", "rgb_1", "rgb_2", "len", "property_1"}));
    EXPECT_EQ(lines.attribute("fa")->values, (std::vector<float>{0.1f, 0.2f, 0.3f, 0.5f, 0.6f}));
    EXPECT_EQ(lines.attribute("rgb_2")->values, (std::vector<float>{3, 6, 9, 0, 1}));
    // Properties are per track, repeated along it.
    EXPECT_EQ(lines.attribute("len")->values, (std::vector<float>{42, 42, 42, 7, 7}));
    EXPECT_EQ(lines.attribute("property_1")->values, (std::vector<float>{-1, -1, -1, -2, -2}));
}

TEST(TrkReader, LittleEndianV2AppliesVoxToRasAndExpandsProperties) {
    Bytes b = makeTrk(false, 2, sampleTracks());
    MemorySource source("a.trk", b.data(), b.size());
    expectSampleTrk(readTrk(source), true);
}

TEST(TrkReader, BigEndianGivesTheSameLinesAsLittleEndian) {
    Bytes b = makeTrk(true, 2, sampleTracks());
    MemorySource source("a.trk", b.data(), b.size());
    expectSampleTrk(readTrk(source), true);
}

TEST(TrkReader, VersionOneKeepsVoxmmCoordinates) {
    Bytes b = makeTrk(false, 1, sampleTracks());
    MemorySource source("a.trk", b.data(), b.size());
    expectSampleTrk(readTrk(source), false);
}

TEST(TrkReader, ZeroNCountMeansReadToTheEnd) {
    Bytes b = makeTrk(true, 2, sampleTracks(), 0);
    MemorySource source("a.trk", b.data(), b.size());
    expectSampleTrk(readTrk(source), true);
}

TEST(TrkReader, NaNVerticesAreDroppedAndCountedByCleaning) {
    auto tracks = sampleTracks();
    tracks[0].points[1] = {kNaN, 0, 0};
    Bytes b = makeTrk(false, 1, tracks);
    MemorySource source("a.trk", b.data(), b.size());
    LineSet lines = readTrk(source);
    CleanReport report = cleanLineSet(lines);
    EXPECT_EQ(report.nonFiniteVertices, 1u);
    EXPECT_EQ(report.droppedPolylines, 2u);  // the NaN splits track 0 into two 1-vertex pieces
    EXPECT_EQ(lines.polylineCount(), 1u);
}

TEST(TrkReader, MalformedFilesNameTheByteOffset) {
    const Bytes good = makeTrk(false, 2, sampleTracks());
    auto trk = [](const ByteSource& s) { readTrk(s); };

    Bytes shortHeader(good.begin(), good.begin() + 500);
    std::string e = errorOf(trk, shortHeader, "a.trk");
    EXPECT_CONTAINS(e, "a.trk: byte 500: truncated TrackVis header");

    Bytes magic = good;
    magic[0] = 'X';
    EXPECT_CONTAINS(errorOf(trk, magic), "byte 0: not a TrackVis file");

    Writer w{good};
    w.putAt<std::int32_t>(996, 999);
    EXPECT_CONTAINS(errorOf(trk, w.bytes), "byte 996: hdr_size is 999");

    w = Writer{good};
    w.putAt<std::int32_t>(992, 4);
    EXPECT_CONTAINS(errorOf(trk, w.bytes), "byte 992: unsupported version 4");

    w = Writer{good};
    w.putAt<std::int16_t>(36, -1);
    EXPECT_CONTAINS(errorOf(trk, w.bytes), "byte 36: n_scalars is -1");

    w = Writer{good};
    w.putAt<std::int16_t>(238, 30000);
    EXPECT_CONTAINS(errorOf(trk, w.bytes), "byte 238: n_properties is 30000");

    // Count bomb: the first track claims 2^31 - 1 points.
    w = Writer{good};
    w.putAt<std::int32_t>(1000, std::numeric_limits<std::int32_t>::max());
    e = errorOf(trk, w.bytes);
    EXPECT_CONTAINS(e, "byte 1000: track 0 declares 2147483647 points");

    // Truncated inside the second track.
    Bytes cut(good.begin(), good.end() - 6);
    e = errorOf(trk, cut);
    EXPECT_CONTAINS(e, "track 1 declares 2 points");

    // Truncated inside the second track's point count (n_count 0: read to the end).
    const std::size_t firstTrack = 4 + 3 * 4 * 7 + 4 * 2;  // count, 3 points of 7 floats, 2 properties
    w = Writer{Bytes(good.begin(), good.begin() + std::ptrdiff_t(1000 + firstTrack + 2))};
    w.putAt<std::int32_t>(988, 0);
    EXPECT_CONTAINS(errorOf(trk, w.bytes),
                    "byte " + std::to_string(1000 + firstTrack) + ": truncated: track 1 has no complete point count");

    // A voxel size of 0 cannot map voxmm to RAS.
    w = Writer{good};
    w.putAt<float>(16, 0.0f);
    EXPECT_CONTAINS(errorOf(trk, w.bytes), "byte 16: voxel_size[1] is 0");
}

// What nibabel reads (with a warning or silently) is read, with a warning naming the position.
TEST(TrkReader, NCountDisagreeingWithTheTracksIsAWarningAsInNibabel) {
    const Bytes good = makeTrk(false, 2, sampleTracks());

    // n_count larger than what the file holds: the tracks there are.
    Writer w{good};
    w.putAt<std::int32_t>(988, 3);
    MemorySource more("a.trk", w.bytes.data(), w.bytes.size());
    expectSampleTrk(readTrk(more), true);
    EXPECT_EQ(more.warnings(), (std::vector<std::string>{"byte " + std::to_string(good.size()) +
                                                         ": file ends after 2 of the n_count 3 tracks; read 2"}));

    // n_count smaller: n_count tracks, the bytes after them ignored.
    w = Writer{good};
    w.putAt<std::int32_t>(988, 1);
    MemorySource fewer("a.trk", w.bytes.data(), w.bytes.size());
    const LineSet lines = readTrk(fewer);
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 3}));
    EXPECT_EQ(lines.attribute("len")->values, (std::vector<float>{42, 42, 42}));
    const std::size_t firstTrack = 4 + 3 * 4 * 7 + 4 * 2;
    EXPECT_EQ(fewer.warnings(),
              (std::vector<std::string>{"byte " + std::to_string(1000 + firstTrack) + ": " +
                                        std::to_string(good.size() - 1000 - firstTrack) +
                                        " bytes after the last of the n_count 1 tracks (n_count wrong?); ignored"}));

    // A file of the right n_count has nothing to say.
    MemorySource right("a.trk", good.data(), good.size());
    readTrk(right);
    EXPECT_TRUE(right.warnings().empty());
}

TEST(TrkReader, EmptyTractogramIsAValidEmptyLineSet) {
    for (int nCount : {0, 5}) {
        const Bytes b = makeTrk(true, 2, {}, nCount);
        MemorySource source("empty.trk", b.data(), b.size());
        const LineSet lines = readTrk(source);
        EXPECT_EQ(lines.polylineCount(), 0u);
        EXPECT_EQ(lines.vertexCount(), 0u);
        ASSERT_EQ(lines.attributes.size(), 6u);  // the header's names, without values
        EXPECT_TRUE(lines.attributes[0].values.empty());
        EXPECT_EQ(source.warnings().size(), nCount == 0 ? 0u : 1u);
    }
}

TEST(TrkReader, VersionThreeIsReadAsVersionTwoAsInNibabel) {
    Writer w{makeTrk(false, 2, sampleTracks())};
    w.putAt<std::int32_t>(992, 3);
    MemorySource source("a.trk", w.bytes.data(), w.bytes.size());
    expectSampleTrk(readTrk(source), true);
    EXPECT_EQ(source.warnings(), (std::vector<std::string>{"byte 992: version 3 is read as version 2"}));
}

TEST(TrkReader, NameValueCountsNibabelToleratesAreWarnings) {
    // "rgb" claims 9 values where 3 are left (n_scalars 4, "fa" took one): it names those 3.
    Writer w{makeTrk(false, 2, sampleTracks())};
    std::memcpy(w.bytes.data() + 58,
                "rgb\0"
                "9",
                5);
    MemorySource over("a.trk", w.bytes.data(), w.bytes.size());
    expectSampleTrk(readTrk(over), true);
    EXPECT_EQ(over.warnings(),
              (std::vector<std::string>{"byte 58: name \"rgb\" covers 9 values, more than the 4 declared; it "
                                        "names the 3 left"}));

    // A name of 0 values is skipped (nibabel's TrkFile.load does the same); its values go to the
    // next name or to scalar_i.
    w = Writer{makeTrk(false, 2, sampleTracks())};
    std::memcpy(w.bytes.data() + 58,
                "rgb\0"
                "0",
                5);
    MemorySource zero("a.trk", w.bytes.data(), w.bytes.size());
    const LineSet lines = readTrk(zero);
    std::vector<std::string> names;
    for (const Attribute& a : lines.attributes) names.push_back(a.name);
    EXPECT_EQ(names, (std::vector<std::string>{"fa", "scalar_1", "scalar_2", "scalar_3", "len", "property_1"}));
    EXPECT_EQ(lines.attribute("scalar_3")->values, (std::vector<float>{3, 6, 9, 0, 1}));
    EXPECT_EQ(zero.warnings(), (std::vector<std::string>{"byte 58: name \"rgb\": value count 0; the name is skipped"}));
}

// ---- .tck / .tsf ----------------------------------------------------------------------------

// An MRtrix file: `magic` header with `extra` lines, then `values` as Float32/64 LE/BE.
template <class T = float>
Bytes makeMrtrix(const std::string& magic, const std::vector<T>& values, bool big, const std::string& extra = "",
                 bool fileLine = true) {
    const std::string type = std::string(sizeof(T) == 4 ? "Float32" : "Float64") + (big ? "BE" : "LE");
    std::string head = magic + "\ntimestamp: 1700000000.1\ndatatype: " + type + "\n" + extra;
    // The offset is part of the header it points past: pad to a fixed width.
    std::string fileKey = fileLine ? "file: . " : "";
    std::size_t offset = head.size() + fileKey.size() + 8 + 1 + 4;
    char number[16];
    std::snprintf(number, sizeof number, "%-8zu", offset);
    if (fileLine) head += fileKey + number + "\n";
    head += "END\n";
    Writer w;
    w.big = big;
    w.text(head);
    w.bytes.resize(offset, 0);
    for (T v : values) w.put(v);
    return w.bytes;
}

template <class T = float>
std::vector<T> sampleTckValues() {
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    return {0, 0, 0, 1, 0, 0, 1, 1, 0, nan, nan, nan, 5, 5, 5, 6, 6, 6, nan, nan, nan, inf, inf, inf};
}

void expectSampleTck(const LineSet& lines) {
    ASSERT_EQ(lines.polylineCount(), 2u);
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 3, 5}));
    EXPECT_EQ(lines.positions[2], glm::vec3(1, 1, 0));
    EXPECT_EQ(lines.positions[4], glm::vec3(6, 6, 6));
    EXPECT_TRUE(lines.attributes.empty());
}

TEST(TckReader, Float32LittleAndBigEndian) {
    for (bool big : {false, true}) {
        Bytes b = makeMrtrix("mrtrix tracks", sampleTckValues(), big, "count: 2\n");
        MemorySource source("a.tck", b.data(), b.size());
        SCOPED_TRACE(big ? "BE" : "LE");
        expectSampleTck(readTck(source));
    }
}

TEST(TckReader, Float64) {
    Bytes b = makeMrtrix("mrtrix tracks", sampleTckValues<double>(), true);
    MemorySource source("a.tck", b.data(), b.size());
    expectSampleTck(readTck(source));
}

TEST(TckReader, TsfFilesNextToTheTracksBecomeAttributes) {
    const std::string dir = testDir();
    writeFile(dir + "/tracks.tck", makeMrtrix("mrtrix tracks", sampleTckValues(), false));
    writeFile(dir + "/tracks_fa.tsf",
              makeMrtrix<float>("mrtrix track scalars", {0.1f, 0.2f, 0.3f, kNaN, 0.4f, 0.5f, kNaN, kInf}, true));
    writeFile(dir + "/tracks.tsf",
              makeMrtrix<double>("mrtrix track scalars", {1, 2, 3, NAN, 4, 5, NAN, INFINITY}, false));
    // Belongs to tracks_long.tck, not to tracks.tck.
    writeFile(dir + "/tracks_long.tck", makeMrtrix("mrtrix tracks", sampleTckValues(), false));
    writeFile(dir + "/tracks_long_md.tsf", makeMrtrix<float>("mrtrix track scalars", {1, NAN, INFINITY}, false));

    LineSet lines = readNativeLineFile(dir + "/tracks.tck");
    expectSampleTck(LineSet{lines.positions, lines.offsets, {}, {}, {}});
    ASSERT_EQ(lines.attributes.size(), 2u);
    EXPECT_EQ(lines.attributes[0].name, "fa");
    EXPECT_EQ(lines.attributes[0].values, (std::vector<float>{0.1f, 0.2f, 0.3f, 0.4f, 0.5f}));
    EXPECT_EQ(lines.attributes[1].name, "tsf");
    EXPECT_EQ(lines.attributes[1].values, (std::vector<float>{1, 2, 3, 4, 5}));

    // The long one's .tsf has the wrong shape for it: an error naming the .tsf and the offset.
    std::string e = inputErrorOf([&] { readNativeLineFile(dir + "/tracks_long.tck"); });
    EXPECT_CONTAINS(e, "tracks_long_md.tsf: byte ");
    EXPECT_CONTAINS(e, "track 0 has 1 values, the tracks file has 3 vertices");
}

TEST(TckReader, PartlyNaNVerticesAreKeptForCleaningToCount) {
    std::vector<float> v = sampleTckValues();
    v[3] = kNaN;  // vertex 1 = (NaN, 0, 0): not a delimiter
    Bytes b = makeMrtrix("mrtrix tracks", v, false);
    MemorySource source("a.tck", b.data(), b.size());
    LineSet lines = readTck(source);
    EXPECT_EQ(lines.vertexCount(), 5u);
    EXPECT_EQ(cleanLineSet(lines).nonFiniteVertices, 1u);
}

TEST(TckReader, MalformedFilesNameTheLineOrByteOffset) {
    auto tck = [](const ByteSource& s) { readTck(s); };
    const Bytes good = makeMrtrix("mrtrix tracks", sampleTckValues(), false, "count: 2\n");

    Bytes magic = good;
    magic[0] = 'X';
    EXPECT_CONTAINS(errorOf(tck, magic, "a.tck"), "a.tck: line 1: not an MRtrix file");

    std::string text(good.begin(), good.end());
    Bytes noEnd(good.begin(), good.begin() + std::ptrdiff_t(text.find("END")));
    EXPECT_CONTAINS(errorOf(tck, noEnd), "line 6: header has no END line");

    EXPECT_CONTAINS(errorOf(tck, makeMrtrix("mrtrix tracks", sampleTckValues(), false, "datatype: Int16LE\n")),
                    "line 4: unsupported datatype \"Int16LE\"");
    EXPECT_CONTAINS(errorOf(tck, makeMrtrix("mrtrix tracks", sampleTckValues(), false, "file: data.dat 0\n")),
                    "line 4: data in a separate file");
    // A line without a colon continues the field before it; right after the first line there is
    // none (nibabel's tck.py refuses it too).
    Bytes garbage = good;
    const std::string inserted = "garbage\n";
    garbage.insert(garbage.begin() + std::ptrdiff_t(text.find('\n') + 1), inserted.begin(), inserted.end());
    EXPECT_CONTAINS(errorOf(tck, garbage), "line 2: expected \"key: value\"");
    EXPECT_CONTAINS(errorOf(tck, makeMrtrix("mrtrix tracks", sampleTckValues(), false, "", false)),
                    "no \"file: . OFFSET\" line");

    // Offset past the end of the file (a count bomb for the data).
    std::string bomb = text;
    std::size_t at = bomb.find("file: . ") + 8;
    bomb.replace(at, 8, "99999999");
    EXPECT_CONTAINS(errorOf(tck, Bytes(bomb.begin(), bomb.end())), "byte 99999999: data offset 99999999");

    // Truncated: the Inf terminator and part of the last triplet are missing.
    Bytes cut(good.begin(), good.end() - 16);
    EXPECT_CONTAINS(errorOf(tck, cut), "truncated: the data ends without the Inf end-of-file triplet");
    // The position is the start of the incomplete triplet.
    EXPECT_CONTAINS(errorOf(tck, cut), "byte " + std::to_string(good.size() - 24) + ":");

    // Truncated inside a track: whole triplets, but the last track has no NaN triplet and there
    // is no Inf triplet (MRtrix would drop the track silently).
    Bytes insideTrack(good.begin(), good.end() - 24);
    EXPECT_CONTAINS(errorOf(tck, insideTrack),
                    "byte " + std::to_string(good.size() - 24) +
                        ": truncated: the data ends without the Inf end-of-file triplet, inside track 1 (after 2 "
                        "of its vertices)");
}

// Small hand-written files as other tools write them: MRtrix (count after the data offset, a
// padded first line, total_count), MATLAB (multi-line values), a tool that stopped early.

Bytes bytesOf(const std::string& header, const std::vector<float>& values) {
    Writer w;
    w.text(header);
    for (float v : values) w.put(v);
    return w.bytes;
}

// `header` with "file: . OFFSET" filled in: OFFSET is the header's length (the placeholder
// "@@@@" is four digits wide, so the length does not change).
std::string withOffset(std::string header) {
    const std::size_t at = header.find("@@@@");
    char number[8];
    std::snprintf(number, sizeof number, "%4zu", header.size());
    header.replace(at, 4, number);
    return header;
}

TEST(TckReader, StaleCountIsAWarningAndTheDataDecides) {
    // As MRtrix writes it: the first line padded, count (stale: a writer that stopped before
    // updating it) after the file line, total_count.
    const std::string header = withOffset(
        "mrtrix tracks    \ntimestamp: 1700000000.1\ndatatype: Float32LE\nfile: . @@@@\ncount: 0\n"
        "total_count: 0\nEND\n");
    const Bytes stale = bytesOf(header, sampleTckValues());
    MemorySource source("a.tck", stale.data(), stale.size());
    expectSampleTck(readTck(source));
    EXPECT_EQ(source.warnings(),
              (std::vector<std::string>{"line 5: count: 0 tracks declared, the data holds 2; read 2"}));

    // Larger than the data (a MATLAB script that dropped tracks and kept the header's count).
    const Bytes more = makeMrtrix("mrtrix tracks", sampleTckValues(), false, "count: 7\n");
    MemorySource moreSource("a.tck", more.data(), more.size());
    expectSampleTck(readTck(moreSource));
    EXPECT_EQ(moreSource.warnings(),
              (std::vector<std::string>{"line 4: count: 7 tracks declared, the data holds 2; read 2"}));

    // Not a number: ignored, with a warning.
    const Bytes word = makeMrtrix("mrtrix tracks", sampleTckValues(), false, "count: many\n");
    MemorySource wordSource("a.tck", word.data(), word.size());
    expectSampleTck(readTck(wordSource));
    EXPECT_EQ(wordSource.warnings(),
              (std::vector<std::string>{"line 4: count: expected a non-negative integer, got \"many\"; ignored"}));
}

TEST(TckReader, MultiLineHeaderValuesAndCommentsAreRead) {
    // MATLAB's write_mrtrix_tracks.m writes a cell-array value as lines after its key; MRtrix
    // repeats the key. Comments run from '#' to the end of the line; keys are case-insensitive.
    const std::string header = withOffset(
        "mrtrix tracks\n"
        "# written by hand\n"
        "command_history: tckgen fod.mif a.tck -select 2\n"
        "tckedit a.tck b.tck -include roi.mif\n"
        "   tckresample b.tck c.tck\n"
        "comment: first\n"
        "comment: second # and a remark\n"
        "Datatype: float32le\n"
        "count: 2  # as written\n"
        "file: . @@@@\n"
        "END\n");
    const Bytes b = bytesOf(header, sampleTckValues());
    MemorySource source("a.tck", b.data(), b.size());
    expectSampleTck(readTck(source));
    EXPECT_TRUE(source.warnings().empty()) << source.warnings().front();
}

TEST(TckReader, EmptyTractogramIsAValidEmptyLineSet) {
    // As MRtrix and nibabel write it: count 0 and the Inf triplet.
    const float inf = kInf;
    const Bytes empty = makeMrtrix<float>("mrtrix tracks", {inf, inf, inf}, false, "count: 0\n");
    MemorySource source("empty.tck", empty.data(), empty.size());
    const LineSet lines = readTck(source);
    EXPECT_EQ(lines.polylineCount(), 0u);
    EXPECT_EQ(lines.vertexCount(), 0u);
    EXPECT_TRUE(source.warnings().empty());

    // No data at all: read to the end, with a warning for the missing Inf triplet.
    const Bytes bare = makeMrtrix<float>("mrtrix tracks", {}, false, "count: 0\n");
    MemorySource bareSource("empty.tck", bare.data(), bare.size());
    EXPECT_EQ(readTck(bareSource).polylineCount(), 0u);
    EXPECT_EQ(bareSource.warnings(),
              (std::vector<std::string>{"byte " + std::to_string(bare.size()) +
                                        ": the data ends without the Inf end-of-file triplet; read to the end (0 "
                                        "tracks)"}));
}

TEST(TckReader, DataEndingBetweenTracksWithoutTheInfTripletIsReadToTheEnd) {
    // A writer that stopped after a whole track (MRtrix's Reader stops at the end of the data).
    std::vector<float> values = sampleTckValues();
    values.resize(values.size() - 3);  // no Inf triplet
    const Bytes b = makeMrtrix("mrtrix tracks", values, false, "count: 2\n");
    MemorySource source("a.tck", b.data(), b.size());
    expectSampleTck(readTck(source));
    EXPECT_EQ(source.warnings(),
              (std::vector<std::string>{"byte " + std::to_string(b.size()) +
                                        ": the data ends without the Inf end-of-file triplet; read to the end (2 "
                                        "tracks)"}));
}

TEST(TsfReader, MismatchedTrackCountNamesTheOffset) {
    Bytes tck = makeMrtrix("mrtrix tracks", sampleTckValues(), false);
    MemorySource tckSource("a.tck", tck.data(), tck.size());
    LineSet lines = readTck(tckSource);
    auto tsfError = [&](const std::vector<float>& values) {
        Bytes b = makeMrtrix("mrtrix track scalars", values, false);
        return errorOf([&](const ByteSource& s) { readTsf(s, lines); }, b, "a.tsf");
    };
    EXPECT_CONTAINS(tsfError({1, 2, 3, kNaN, kInf}), "a.tsf: byte ");
    EXPECT_CONTAINS(tsfError({1, 2, 3, kNaN, kInf}), "holds 1 tracks, the tracks file 2");
    EXPECT_CONTAINS(tsfError({1, 2, 3, kNaN, 4, 5, kNaN, 6, kNaN, kInf}), "more tracks than the 2");
    EXPECT_CONTAINS(tsfError({1, 2, 3, kNaN, 4, 5, kNaN}), "truncated");
    EXPECT_CONTAINS(errorOf([&](const ByteSource& s) { readTsf(s, lines); }, tck), "line 1: not an MRtrix file");
}

// ---- .obj -----------------------------------------------------------------------------------

LineSet readObjText(const std::string& text) {
    MemorySource source("a.obj", text.data(), text.size());
    return readObjLines(source);
}

TEST(ObjReader, LineVisStyleAttributesAndNames) {
    LineSet lines = readObjText(
        "# LineVis export\n"
        "a vorticity speed\n"
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 0 2 0\n"
        "vt 10 0.5\nvt 11 0.6\nvt 12 0.7\nvt 13 0.8\nvt 14 0.9\n"
        "g line0\n"
        "l 1 2 3\n"
        "l -1 -2\n"    // relative: vertices 5, 4
        "f 1 2 3\n");  // faces are ignored
    EXPECT_EQ(lines.offsets, (std::vector<std::uint32_t>{0, 3, 5}));
    EXPECT_EQ(lines.positions[3], glm::vec3(0, 2, 0));
    ASSERT_EQ(lines.attributes.size(), 2u);
    EXPECT_EQ(lines.attributes[0].name, "vorticity");
    EXPECT_EQ(lines.attributes[0].values, (std::vector<float>{10, 11, 12, 14, 13}));
    EXPECT_EQ(lines.attributes[1].name, "speed");
}

TEST(ObjReader, ExplicitVtIndicesAndUnnamedAttributes) {
    LineSet lines = readObjText("v 0 0 0\nv 1 0 0\nvt 5\nvt 6\nl 1/2 2/1\nl 2//3 1\n");
    ASSERT_EQ(lines.attributes.size(), 1u);
    EXPECT_EQ(lines.attributes[0].name, "vt_0");
    EXPECT_EQ(lines.attributes[0].values, (std::vector<float>{6, 5, 6, 5}));
}

TEST(ObjReader, NaNVertexIsCountedByCleaning) {
    LineSet lines = readObjText("v 0 0 0\nv nan 0 0\nv 1 0 0\nv 2 0 0\nl 1 2 3 4\n");
    CleanReport r = cleanLineSet(lines);
    EXPECT_EQ(r.nonFiniteVertices, 1u);
    EXPECT_EQ(lines.polylineCount(), 1u);  // 1 | 3 4: the single vertex piece is dropped
}

TEST(ObjReader, MalformedFilesNameTheLine) {
    auto err = [](const std::string& text) { return inputErrorOf([&] { readObjText(text); }); };
    EXPECT_CONTAINS(err("v 0 0 0\nv 1 0 0\nl 1 3\n"), "a.obj: line 3: vertex index 3 out of range (2 defined so far)");
    EXPECT_CONTAINS(err("v 0 0 0\nv 1 zero 0\n"), "a.obj: line 2: expected a number, got \"zero\"");
    EXPECT_CONTAINS(err("v 0 0\n"), "line 1: \"v\" needs 3 coordinates");
    EXPECT_CONTAINS(err("v 0 0 0\nvt 1 2\nvt 1\n"), "line 3: \"vt\" with 1 values, earlier rows have 2");
    EXPECT_CONTAINS(err("a x y\nv 0 0 0\nvt 1\n"), "line 1: 2 attribute names, but \"vt\" rows have 1 values");
    EXPECT_CONTAINS(err("v 0 0 0\nv 1 0 0\nv 2 0 0\nvt 1\nl 1 2 3\n"), "line 5: vertex 2 has no \"vt\" row (1 rows)");
    EXPECT_CONTAINS(err("v 0 0 0\nl 1 0\n"), "line 2: expected a vertex index");
    EXPECT_CONTAINS(err("v 0 0 0\nvt 1\nl 1/7\n"), "line 3: vt index 7 out of range");
}

TEST(ObjReader, IndexRepetitionBombIsRejectedBeforeAllocating) {
    // 256 attributes per vertex, then one "l" repeating vertex 1: ~1 MB of text that would
    // expand to ~500 MB of polyline vertices.
    std::string text = "v 0 0 0\nvt";
    for (int i = 0; i < 256; ++i) text += " 1";
    text += "\nl";
    for (int i = 0; i < 500000; ++i) text += " 1";
    text += "\n";
    EXPECT_CONTAINS(inputErrorOf([&] { readObjText(text); }), "a.obj: byte 0: the polylines would need");
}

// ---- .tcb -----------------------------------------------------------------------------------

LineSet sampleLines() {
    LineSet lines;
    lines.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {5, 5, 5}, {6, 6, 7}};
    lines.offsets = {0, 3, 5};
    lines.attributes = {{"speed", {1, 2, 3, 4, 5}}, {"vorticity_x", {-1, kNaN, 0.5f, 1e30f, 0}}};
    return lines;
}

TEST(TcbFormat, RoundTripIsExact) {
    const std::string path = testDir() + "/lines.tcb";
    const LineSet original = sampleLines();
    writeTcb(original, path);
    LineSet read = readNativeLineFile(path);
    EXPECT_EQ(read.positions, original.positions);
    EXPECT_EQ(read.offsets, original.offsets);
    ASSERT_EQ(read.attributes.size(), 2u);
    for (std::size_t a = 0; a < 2; ++a) {
        EXPECT_EQ(read.attributes[a].name, original.attributes[a].name);
        // Bitwise, NaN included.
        EXPECT_EQ(std::memcmp(read.attributes[a].values.data(), original.attributes[a].values.data(), 20), 0);
    }
    // Size = 40 header + names (4+5 + 4+11 = 24, padded to 64) + 3 offsets + 5 positions + 2x5 values.
    EXPECT_EQ(fs::file_size(path), 64u + 12 + 60 + 40);
}

TEST(TcbFormat, NoAttributesNoPolylineBytes) {
    const std::string path = testDir() + "/lines.tcb";
    LineSet lines = sampleLines();
    lines.attributes.clear();
    writeTcb(lines, path);
    EXPECT_EQ(readNativeLineFile(path).positions, lines.positions);
}

Bytes sampleTcbBytes() {
    const std::string path = testDir() + "/s.tcb";
    writeTcb(sampleLines(), path);
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

TEST(TcbFormat, MalformedFilesNameTheByteOffset) {
    auto tcb = [](const ByteSource& s) { readTcb(s); };
    const Bytes good = sampleTcbBytes();
    auto with = [&](std::size_t offset, auto value) {
        Writer w{good};
        w.putAt(offset, value);
        return errorOf(tcb, w.bytes, "a.tcb");
    };
    EXPECT_CONTAINS(errorOf(tcb, Bytes(good.begin(), good.begin() + 20), "a.tcb"),
                    "a.tcb: byte 20: truncated .tcb header");
    EXPECT_CONTAINS(with(0, std::uint8_t('X')), "a.tcb: byte 0: not a .tcb file");
    EXPECT_CONTAINS(with(8, std::uint32_t(2)), "byte 8: unsupported .tcb version 2");
    EXPECT_CONTAINS(with(12, std::uint32_t(1u << 20)), "byte 12: attribute count 1048576");
    EXPECT_CONTAINS(with(16, std::uint64_t(1) << 40), "byte 16: vertex count 1099511627776 does not fit");
    EXPECT_CONTAINS(with(24, std::uint64_t(1) << 62), "byte 24: polyline count");
    EXPECT_CONTAINS(with(32, ~std::uint64_t(0)), "byte 32: name table size");
    EXPECT_CONTAINS(with(40, std::uint32_t(4000)), "byte 40: attribute 0: name length 4000");
    EXPECT_CONTAINS(with(49, std::uint32_t(0)), "byte 49: attribute 1: name length 0");
    // Offsets at 64: [0, 3, 5].
    EXPECT_CONTAINS(with(64, std::uint32_t(1)), "byte 64: first polyline offset is 1");
    EXPECT_CONTAINS(with(68, std::uint32_t(9)), "byte 72: polyline offsets decrease (9 then 5)");
    EXPECT_CONTAINS(with(72, std::uint32_t(4)), "byte 72: last polyline offset 4 is not the vertex count 5");
    std::string e = errorOf(tcb, Bytes(good.begin(), good.end() - 1), "a.tcb");
    EXPECT_CONTAINS(e, "a.tcb: byte " + std::to_string(good.size() - 1) + ": file size");
    EXPECT_CONTAINS(e, "truncated");
    Bytes longer = good;
    longer.push_back(0);
    EXPECT_CONTAINS(errorOf(tcb, longer), "does not match the header");
}

// ---- dispatch -------------------------------------------------------------------------------

TEST(NativeLineFile, MissingFileAndUnknownExtension) {
    const std::string dir = testDir();
    EXPECT_CONTAINS(inputErrorOf([&] { readNativeLineFile(dir + "/none.trk"); }), "none.trk: no such file");
    EXPECT_TRUE(isNativeLineFormat(".tcb"));
    EXPECT_FALSE(isNativeLineFormat(".vtp"));
}

}  // namespace
}  // namespace tc
