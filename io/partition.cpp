// Partitioned line sets (io/partition.h); the layout is specified in docs/formats.md,
// "Partitioned line sets".
#include "io/partition.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#include "core/error.h"
#include "core/spec_reader.h"
#include "io/atomic_file.h"
#include "io/byte_source.h"
#include "io/json_file.h"
#include "io/line_formats.h"

namespace tc {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kFormat = "tubecast-partition";
constexpr const char* kIndexName = "index.json";
constexpr char kRunsMagic[8] = {'T', 'C', 'B', 'R', 'U', 'N', 'S', '\0'};
// Version 2 adds the tangent each run's source polyline carries into it (incomingTangents); a
// version 1 file has none and still reads.
constexpr std::uint32_t kRunsVersion = 2;
constexpr std::size_t kRunsHeaderBytes = 24;
constexpr std::size_t kRunBytes = 16;
constexpr std::size_t kTangentBytes = 12;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

// --- region-K.runs ---------------------------------------------------------------------------

void writeRuns(const std::vector<RunOrigin>& origins, const std::vector<glm::vec3>& tangents, const std::string& path) {
    static_assert(sizeof(RunOrigin) == kRunBytes, "runs are written as two packed u64");
    static_assert(sizeof(glm::vec3) == kTangentBytes, "tangents are written as three packed f32");
    TC_CHECK_OP(tangents.size(), ==, origins.size());
    std::uint8_t header[kRunsHeaderBytes] = {};
    std::memcpy(header, kRunsMagic, 8);
    const std::uint32_t version = kRunsVersion;
    const std::uint64_t count = origins.size();
    std::memcpy(header + 8, &version, 4);
    std::memcpy(header + 16, &count, 8);
    AtomicFile file(path);
    {
        std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(file.tempPath().c_str(), "wb"), &std::fclose);
        if (!f) throw OutputError(path + ": cannot write: " + std::strerror(errno));
        auto put = [&](const void* data, std::size_t bytes) {
            if (bytes && std::fwrite(data, 1, bytes, f.get()) != bytes)
                throw OutputError(path + ": cannot write: " + std::strerror(errno));
        };
        put(header, sizeof header);
        put(origins.data(), kRunBytes * origins.size());
        put(tangents.data(), kTangentBytes * tangents.size());
        if (std::fclose(f.release()) != 0) throw OutputError(path + ": cannot write: " + std::strerror(errno));
    }
    file.commit();
}

// `tangents`, when given, receives each run's incoming tangent (empty from a version 1 file).
std::vector<RunOrigin> readRuns(const std::string& path, std::uint64_t expectedRuns,
                                std::vector<glm::vec3>* tangents = nullptr) {
    FileSource source(path);
    std::uint8_t h[kRunsHeaderBytes];
    if (source.size() < kRunsHeaderBytes)
        source.failAt(source.size(), "truncated runs header (" + std::to_string(source.size()) + " of 24 bytes)");
    source.read(0, h, kRunsHeaderBytes, "the header");
    if (std::memcmp(h, kRunsMagic, 8) != 0) source.failAt(0, "not a runs file (no \"TCBRUNS\" magic)");
    const auto version = loadLittle<std::uint32_t>(h + 8);
    if (version != 1 && version != kRunsVersion)
        source.failAt(8, "unsupported runs version " + std::to_string(version) + " (this build reads versions 1 and " +
                             std::to_string(kRunsVersion) + ")");
    const std::size_t perRun = kRunBytes + (version >= 2 ? kTangentBytes : 0);
    const auto count = loadLittle<std::uint64_t>(h + 16);
    if (count != expectedRuns)
        source.failAt(16,
                      std::to_string(count) + " runs, the brick has " + std::to_string(expectedRuns) + " polylines");
    if (source.size() != kRunsHeaderBytes + perRun * count)
        source.failAt(source.size(), "file size " + std::to_string(source.size()) + " does not match " +
                                         std::to_string(count) + " runs (" +
                                         std::to_string(kRunsHeaderBytes + perRun * count) + " bytes)");
    std::vector<RunOrigin> origins(count);
    source.read(kRunsHeaderBytes, origins.data(), kRunBytes * count, "the runs");
    if (tangents) {
        tangents->clear();
        if (version >= 2) {
            tangents->resize(count);
            source.read(kRunsHeaderBytes + kRunBytes * count, tangents->data(), kTangentBytes * count, "the tangents");
        }
    }
    return origins;
}

// --- index.json ------------------------------------------------------------------------------

// Infinite faces as null: JSON has no infinity.
json facesJson(const glm::vec3& v) {
    json a = json::array();
    for (int i = 0; i < 3; ++i) a.push_back(std::isfinite(v[i]) ? json(double(v[i])) : json(nullptr));
    return a;
}

json optionalNumber(float v) {
    return std::isnan(v) ? json(nullptr) : json(double(v));
}

std::uint64_t getCount(SpecReader& r, const std::string& key) {
    const json& v = r.raw(key);
    if (!v.is_number_unsigned()) r.fail(key, "expected a count (an integer >= 0), got " + describeJson(v));
    return v.get<std::uint64_t>();
}

// An array of 3 numbers, null standing for `infinite` (-inf for lo, +inf for hi).
glm::vec3 getFaces(SpecReader& r, const std::string& key, float infinite) {
    const json& v = r.raw(key);
    auto valid = [&] {
        if (!v.is_array() || v.size() != 3) return false;
        for (const json& e : v)
            if (!e.is_null() && !(e.is_number() && std::isfinite(e.get<double>()))) return false;
        return true;
    };
    if (!valid()) r.fail(key, "expected an array of 3 numbers or nulls, got " + describeJson(v));
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) out[i] = v[std::size_t(i)].is_null() ? infinite : v[std::size_t(i)].get<float>();
    return out;
}

float getOptionalNumber(SpecReader& r, const std::string& key) {
    const json& v = r.raw(key);
    if (v.is_null()) return std::numeric_limits<float>::quiet_NaN();
    if (!v.is_number()) r.fail(key, "expected a number or null, got " + describeJson(v));
    return v.get<float>();
}

std::string getFileName(SpecReader& r, const std::string& key) {
    const std::string name = r.getString(key, "");
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
        name.find('\\') != std::string::npos)
        r.fail(key, "expected a file name in the index's directory, got \"" + name + "\"");
    return name;
}

std::string regionName(int k, const char* extension) {
    return "region-" + std::to_string(k) + extension;
}

json indexJson(const PartitionIndex& index) {
    json attributes = json::array();
    for (const AttributeRange& a : index.attributes)
        attributes.push_back({{"name", a.name}, {"min", optionalNumber(a.min)}, {"max", optionalNumber(a.max)}});
    json regions = json::array();
    for (std::size_t k = 0; k < index.bricks.size(); ++k) {
        const PartitionBrick& b = index.bricks[k];
        regions.push_back({{"region", k},
                           {"file", b.file},
                           {"runs", b.runsFile},
                           {"box", {{"lo", facesJson(b.box.lo)}, {"hi", facesJson(b.box.hi)}}},
                           {"polylines", b.polylines},
                           {"vertices", b.vertices},
                           {"segments", b.segments},
                           {"assigned_segments", b.assignedSegments},
                           {"owned_segments", b.ownedSegments}});
    }
    return {
        {"format", kFormat},
        {"version", kPartitionVersion},
        {"kind", "lines"},
        {"source", index.source},
        {"radius", double(index.radius)},
        {"counts", {{"polylines", index.polylines}, {"vertices", index.vertices}, {"segments", index.segments}}},
        {"bounds", index.bounds.empty() ? json(nullptr)
                                        : json{{"lo", facesJson(index.bounds.lo)}, {"hi", facesJson(index.bounds.hi)}}},
        {"attributes", std::move(attributes)},
        {"velocity", index.velocity},
        {"tree", index.tree.toJson()},
        {"regions", std::move(regions)}};
}

void readBrick(SpecReader& r, int k, const KdDecomposition& tree, PartitionBrick& b) {
    const int region = r.getInt("region", -1, 0, std::numeric_limits<int>::max());
    if (region != k)
        r.fail("region",
               "expected " + std::to_string(k) + " (regions are listed in order), got " + std::to_string(region));
    b.file = getFileName(r, "file");
    b.runsFile = getFileName(r, "runs");
    SpecReader box = r.child("box");
    b.box.lo = getFaces(box, "lo", -kInfinity);
    b.box.hi = getFaces(box, "hi", kInfinity);
    box.finish();
    if (!(b.box == tree.box(k))) r.fail("box", "does not match region " + std::to_string(k) + " of the tree");
    b.polylines = getCount(r, "polylines");
    b.vertices = getCount(r, "vertices");
    b.segments = getCount(r, "segments");
    b.assignedSegments = getCount(r, "assigned_segments");
    b.ownedSegments = getCount(r, "owned_segments");
    if (b.segments + b.polylines != b.vertices)
        r.fail("segments", std::to_string(b.segments) + " segments in " + std::to_string(b.polylines) +
                               " polylines need " + std::to_string(b.segments + b.polylines) +
                               " vertices, the index says " + std::to_string(b.vertices));
    if (b.ownedSegments > b.assignedSegments || b.assignedSegments > b.segments)
        r.fail("owned_segments", "expected owned <= assigned <= segments, got " + std::to_string(b.ownedSegments) +
                                     ", " + std::to_string(b.assignedSegments) + ", " + std::to_string(b.segments));
    r.finish();
}

}  // namespace

std::string PartitionIndex::brickPath(int region) const {
    return (fs::path(directory) / bricks.at(std::size_t(region)).file).string();
}

PartitionIndex writePartition(const LineSet& lines, const KdDecomposition& tree, float radius,
                              const std::string& source, const std::string& directory) {
    PartitionIndex index;
    index.path = (fs::path(directory) / kIndexName).string();
    index.directory = directory;
    index.source = source;
    index.tree = tree;
    index.radius = radius;
    index.polylines = lines.polylineCount();
    index.vertices = lines.vertexCount();
    index.segments = lines.segmentCount();
    index.bounds = lines.bounds;
    index.velocity = lines.velocity;
    for (const Attribute& a : lines.attributes) index.attributes.push_back({a.name, a.min, a.max});

    const RegionItems assigned = assignSegments(tree, lines, radius);
    const std::vector<glm::vec3> transported = transportedTangents(lines);
    for (int k = 0; k < tree.regionCount(); ++k) {
        const std::vector<std::uint32_t>& segments = assigned[std::size_t(k)];
        const RegionLines region = extractRegionLines(lines, segments);
        PartitionBrick& b = index.bricks.emplace_back();
        b.file = regionName(k, ".tcb");
        b.runsFile = regionName(k, ".runs");
        b.box = tree.box(k);
        b.polylines = region.lines.polylineCount();
        b.vertices = region.lines.vertexCount();
        b.segments = region.lines.segmentCount();
        b.assignedSegments = segments.size();
        b.ownedSegments = ownedSegments(tree, k, region.lines).size();
        writeTcb(region.lines, (fs::path(directory) / b.file).string());
        writeRuns(region.origins, incomingTangents(lines, transported, region.origins),
                  (fs::path(directory) / b.runsFile).string());
    }
    writeJsonFile(index.path, indexJson(index));
    return index;
}

bool isPartitionPath(const std::string& path) {
    std::error_code ec;
    if (path.empty()) return false;
    if (fs::is_directory(path, ec)) return fs::is_regular_file(fs::path(path) / kIndexName, ec);
    if (fs::path(path).extension() != ".json" || !fs::is_regular_file(path, ec)) return false;
    try {
        const json doc = readJsonFile(path);
        return doc.is_object() && doc.value("format", json()) == kFormat;
    } catch (const std::exception&) {
        return false;
    }
}

PartitionIndex readPartitionIndex(const std::string& path) {
    std::error_code ec;
    PartitionIndex index;
    if (fs::is_directory(path, ec)) {
        index.path = (fs::path(path) / kIndexName).string();
        if (!fs::exists(index.path, ec))
            throw InputError(path + ": no " + kIndexName +
                             " (not a partitioned data set; `tubecast partition` writes one)");
    } else {
        index.path = path;
    }
    index.directory = fs::path(index.path).parent_path().string();
    if (index.directory.empty()) index.directory = ".";
    const json doc = readJsonFile(index.path);
    SpecReader r(doc, index.path, "");
    if (r.getString("format", "") != kFormat)
        r.fail("format", std::string("expected \"") + kFormat + "\" (not a partitioned data set)");
    const int version = r.getInt("version", -1, 0, std::numeric_limits<int>::max());
    if (version != kPartitionVersion)
        r.fail("version", version < 0 ? "missing required key"
                                      : "unsupported partition version " + std::to_string(version) +
                                            " (this build reads version " + std::to_string(kPartitionVersion) + ")");
    if (r.getEnum("kind", "", {"lines"}).empty()) r.fail("kind", "missing required key");
    index.source = r.getString("source", "");
    index.radius = r.getFloat("radius", 0.0f, 0.0f, std::numeric_limits<float>::max());
    SpecReader counts = r.child("counts");
    index.polylines = getCount(counts, "polylines");
    index.vertices = getCount(counts, "vertices");
    index.segments = getCount(counts, "segments");
    counts.finish();
    if (index.segments + index.polylines != index.vertices)
        r.fail("counts", "segments + polylines must equal vertices, got " + std::to_string(index.segments) + " + " +
                             std::to_string(index.polylines) + " and " + std::to_string(index.vertices));
    if (index.vertices > std::numeric_limits<std::uint32_t>::max())
        r.fail("counts.vertices", "more than 2^32 - 1 vertices do not fit one line set");
    if (!r.raw("bounds").is_null()) {
        SpecReader bounds = r.child("bounds");
        index.bounds.lo = getFaces(bounds, "lo", -kInfinity);
        index.bounds.hi = getFaces(bounds, "hi", kInfinity);
        bounds.finish();
    }
    const json& attributes = r.raw("attributes");
    if (!attributes.is_array()) r.fail("attributes", "expected an array, got " + describeJson(attributes));
    for (std::size_t i = 0; i < attributes.size(); ++i) {
        SpecReader a(attributes[i], index.path, "attributes[" + std::to_string(i) + "]");
        AttributeRange& range = index.attributes.emplace_back();
        range.name = a.getString("name", "");
        if (range.name.empty()) a.fail("name", "expected a non-empty attribute name");
        range.min = getOptionalNumber(a, "min");
        range.max = getOptionalNumber(a, "max");
        a.finish();
    }
    index.velocity = r.getString("velocity", "");
    index.tree = KdDecomposition::fromJson(r.raw("tree"), index.path);
    const json& regions = r.raw("regions");
    if (!regions.is_array() || regions.size() != std::size_t(index.tree.regionCount()))
        r.fail("regions",
               "expected an array of " + std::to_string(index.tree.regionCount()) +
                   " regions (one per region of the tree), got " +
                   (regions.is_array() ? std::to_string(regions.size()) + " entries" : describeJson(regions)));
    std::uint64_t owned = 0;
    for (std::size_t k = 0; k < regions.size(); ++k) {
        SpecReader b(regions[k], index.path, "regions[" + std::to_string(k) + "]");
        readBrick(b, int(k), index.tree, index.bricks.emplace_back());
        owned += index.bricks.back().ownedSegments;
    }
    if (owned != index.segments)
        r.fail("regions", "the regions own " + std::to_string(owned) + " segments, counts.segments is " +
                              std::to_string(index.segments));
    r.finish();
    return index;
}

LineSet readPartitionRegion(const PartitionIndex& index, int region, std::vector<RunOrigin>* origins,
                            std::vector<glm::vec3>* tangents) {
    if (region < 0 || region >= index.regionCount())
        throw InputError(index.path + ": region " + std::to_string(region) + " requested, the set has " +
                         std::to_string(index.regionCount()) + " regions (0.." +
                         std::to_string(index.regionCount() - 1) + ")");
    const PartitionBrick& brick = index.bricks[std::size_t(region)];
    const std::string path = index.brickPath(region);
    const std::string listed = " (region " + std::to_string(region) + " of " + index.path + ")";
    LineSet lines;
    try {
        lines = readTcb(FileSource(path));
    } catch (const InputError& e) {
        throw InputError(e.what() + listed);
    }
    auto mismatch = [&](const char* what, std::uint64_t found, std::uint64_t expected) {
        if (found != expected)
            throw InputError(path + ": " + std::to_string(found) + " " + what + ", " + index.path + " says " +
                             std::to_string(expected));
    };
    mismatch("polylines", lines.polylineCount(), brick.polylines);
    mismatch("vertices", lines.vertexCount(), brick.vertices);
    mismatch("attributes", lines.attributes.size(), index.attributes.size());
    for (std::size_t a = 0; a < lines.attributes.size(); ++a) {
        if (lines.attributes[a].name != index.attributes[a].name)
            throw InputError(path + ": attribute " + std::to_string(a) + " is \"" + lines.attributes[a].name + "\", " +
                             index.path + " says \"" + index.attributes[a].name + "\"");
        lines.attributes[a].min = index.attributes[a].min;
        lines.attributes[a].max = index.attributes[a].max;
    }
    for (std::size_t p = 0; p < lines.polylineCount(); ++p)
        if (lines.offsets[p + 1] - lines.offsets[p] < 2)
            throw InputError(path + ": polyline " + std::to_string(p) + " has fewer than 2 vertices" + listed);
    for (std::size_t v = 0; v < lines.vertexCount(); ++v)
        if (!std::isfinite(lines.positions[v].x) || !std::isfinite(lines.positions[v].y) ||
            !std::isfinite(lines.positions[v].z))
            throw InputError(path + ": vertex " + std::to_string(v) + " is not finite" + listed);
    lines.velocity = index.velocity;
    lines.updateBounds();
    if (origins) {
        const std::string runsPath = (fs::path(index.directory) / brick.runsFile).string();
        try {
            *origins = readRuns(runsPath, lines.polylineCount(), tangents);
        } catch (const InputError& e) {
            throw InputError(e.what() + listed);
        }
    }
    return lines;
}

LineSet readPartitionWhole(const PartitionIndex& index) {
    const std::uint64_t vertexCount = index.vertices, polylineCount = index.polylines;
    LineSet out;
    out.velocity = index.velocity;
    out.positions.resize(vertexCount);
    for (const AttributeRange& a : index.attributes)
        out.attributes.push_back({a.name, std::vector<float>(vertexCount)});
    // Per source segment (by its first vertex): claimed by its owner's brick yet? Per polyline: the
    // vertex range its owned segments cover.
    std::vector<std::uint8_t> claimed(vertexCount, 0);
    std::vector<std::uint64_t> first(polylineCount, std::numeric_limits<std::uint64_t>::max()), last(polylineCount, 0);
    std::uint64_t claimedCount = 0;
    for (int k = 0; k < index.regionCount(); ++k) {
        std::vector<RunOrigin> origins;
        const LineSet brick = readPartitionRegion(index, k, &origins);
        const std::string runsPath = (fs::path(index.directory) / index.bricks[std::size_t(k)].runsFile).string();
        std::uint64_t owned = 0;
        for (std::size_t q = 0; q < brick.polylineCount(); ++q) {
            const RunOrigin o = origins[q];
            const std::uint32_t begin = brick.offsets[q], end = brick.offsets[q + 1];
            if (o.polyline >= polylineCount || o.firstVertex > vertexCount || end - begin > vertexCount - o.firstVertex)
                throw InputError(runsPath + ": run " + std::to_string(q) + " (polyline " + std::to_string(o.polyline) +
                                 ", vertices from " + std::to_string(o.firstVertex) + ") lies outside the source's " +
                                 std::to_string(polylineCount) + " polylines and " + std::to_string(vertexCount) +
                                 " vertices");
            for (std::uint32_t v = begin; v + 1 < end; ++v) {
                if (index.tree.regionOf(segmentMidpoint(brick.positions[v], brick.positions[v + 1])) != k) continue;
                const std::uint64_t g = o.firstVertex + (v - begin);
                if (claimed[g])
                    throw InputError(runsPath + ": run " + std::to_string(q) + ": the segment at source vertex " +
                                     std::to_string(g) + " is owned by two regions");
                claimed[g] = 1;
                ++owned;
                for (std::uint64_t i : {std::uint64_t(0), std::uint64_t(1)}) {
                    out.positions[g + i] = brick.positions[v + i];
                    for (std::size_t a = 0; a < out.attributes.size(); ++a)
                        out.attributes[a].values[g + i] = brick.attributes[a].values[v + i];
                }
                first[o.polyline] = std::min(first[o.polyline], g);
                last[o.polyline] = std::max(last[o.polyline], g + 1);
            }
        }
        if (owned != index.bricks[std::size_t(k)].ownedSegments)
            throw InputError(index.brickPath(k) + ": owns " + std::to_string(owned) + " segments, " + index.path +
                             " says " + std::to_string(index.bricks[std::size_t(k)].ownedSegments));
        claimedCount += owned;
    }
    // The owned segments cover every source segment once (their count is the index's and none was
    // claimed twice); polylines must then follow each other without gaps.
    if (claimedCount != index.segments)
        throw InputError(index.path + ": the bricks own " + std::to_string(claimedCount) +
                         " segments, counts.segments is " + std::to_string(index.segments));
    out.offsets.assign(1, 0);
    for (std::uint64_t p = 0; p < polylineCount; ++p) {
        if (first[p] != out.offsets.back())
            throw InputError(index.path + ": polyline " + std::to_string(p) +
                             (first[p] == std::numeric_limits<std::uint64_t>::max()
                                  ? std::string(" has no segment in any brick")
                                  : " starts at vertex " + std::to_string(first[p]) + ", expected " +
                                        std::to_string(out.offsets.back())));
        out.offsets.push_back(std::uint32_t(last[p] + 1));
    }
    if (out.offsets.back() != vertexCount)
        throw InputError(index.path + ": the polylines end at vertex " + std::to_string(out.offsets.back()) +
                         ", counts.vertices is " + std::to_string(vertexCount));
    for (Attribute& a : out.attributes) a.updateRange();
    out.updateBounds();
    return out;
}

}  // namespace tc
