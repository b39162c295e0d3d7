#include "cli/mpi_render.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <span>

#include "cli/run_manifest.h"
#include "core/default_scene.h"
#include "core/error.h"
#include "core/halo.h"
#include "core/particle_series.h"
#include "core/styling.h"
#include "io/byte_source.h"
#include "io/line_formats.h"
#include "io/line_reader.h"
#include "io/partition.h"

namespace tc::cli {
namespace {

nlohmann::json facesJson(const glm::vec3& v) {
    nlohmann::json a = nlohmann::json::array();
    for (int i = 0; i < 3; ++i) a.push_back(std::isfinite(v[i]) ? nlohmann::json(v[i]) : nlohmann::json(nullptr));
    return a;
}

nlohmann::json boxJson(const RegionBox& b) {
    return {{"lo", facesJson(b.lo)}, {"hi", facesJson(b.hi)}};
}

nlohmann::json boundsJson(const Bounds& b) {
    return {{"lo", {b.lo.x, b.lo.y, b.lo.z}}, {"hi", {b.hi.x, b.hi.y, b.hi.z}}};
}

Bounds boundsOf(const nlohmann::json& j) {
    Bounds b;
    for (int i = 0; i < 3; ++i) {
        b.lo[i] = j["lo"][std::size_t(i)].get<float>();
        b.hi[i] = j["hi"][std::size_t(i)].get<float>();
    }
    return b;
}

// Per run of an extracted region, its source polyline: the id AOV's value (a uint32, as the
// AOV is).
std::vector<std::uint32_t> sourcePolylines(const std::vector<RunOrigin>& origins) {
    std::vector<std::uint32_t> ids(origins.size());
    for (std::size_t q = 0; q < origins.size(); ++q) {
        TC_CHECK(origins[q].polyline < kBackgroundId);
        ids[q] = std::uint32_t(origins[q].polyline);
    }
    return ids;
}

template <typename T>
nlohmann::json::binary_t binaryOf(const std::vector<T>& v) {
    std::vector<std::uint8_t> bytes(v.size() * sizeof(T));
    if (!v.empty()) std::memcpy(bytes.data(), v.data(), bytes.size());
    return nlohmann::json::binary_t(std::move(bytes));
}

template <typename T>
std::vector<T> vectorOf(const nlohmann::json& j) {
    const std::vector<std::uint8_t>& bytes = j.get_binary();
    TC_CHECK_OP(bytes.size() % sizeof(T), ==, 0u);
    std::vector<T> v(bytes.size() / sizeof(T));
    if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
    return v;
}

// A rank's lines as one message: a CBOR header (what the .tcb format does not hold: the source's
// attribute ranges, which automatic styling ranges need, the velocity name, each run's source
// polyline and incoming tangent) and the .tcb bytes.
Bytes packLines(const RegionLines& region, const std::vector<glm::vec3>& tangents) {
    const LineSet& lines = region.lines;
    nlohmann::json header;
    header["velocity"] = lines.velocity;
    header["ranges"] = nlohmann::json::array();
    for (const Attribute& a : lines.attributes) header["ranges"].push_back({a.min, a.max});
    header["polylines"] = binaryOf(sourcePolylines(region.origins));
    header["tangents"] = binaryOf(tangents);
    const Bytes cbor = nlohmann::json::to_cbor(header);
    const Bytes tcb = encodeTcb(lines);
    // Sized once and copied into: GCC 12's -Warray-bounds misreads insert() at the end of an
    // 8-byte vector once packLines is inlined into two callers.
    Bytes out(8 + cbor.size() + tcb.size());
    const std::uint64_t n = cbor.size();
    std::memcpy(out.data(), &n, 8);
    std::copy(cbor.begin(), cbor.end(), out.begin() + 8);
    std::copy(tcb.begin(), tcb.end(), out.begin() + 8 + std::ptrdiff_t(cbor.size()));
    return out;
}

struct UnpackedLines {
    LineSet lines;
    std::vector<std::uint32_t> polylineIds;  // per polyline: its source polyline
    std::vector<glm::vec3> tangents;         // and the tangent it carries in
};

UnpackedLines unpackLines(const Bytes& bytes, const std::string& name) {
    std::uint64_t n = 0;
    TC_CHECK(bytes.size() >= 8);
    std::memcpy(&n, bytes.data(), 8);
    TC_CHECK(8 + n <= bytes.size());
    const nlohmann::json header = nlohmann::json::from_cbor(bytes.begin() + 8, bytes.begin() + 8 + std::ptrdiff_t(n));
    MemorySource source(name, bytes.data() + 8 + n, bytes.size() - 8 - n);
    UnpackedLines out;
    LineSet& lines = out.lines;
    lines = readTcb(source);
    lines.velocity = header["velocity"].get<std::string>();
    const nlohmann::json& ranges = header["ranges"];
    TC_CHECK_OP(ranges.size(), ==, lines.attributes.size());
    for (std::size_t a = 0; a < lines.attributes.size(); ++a) {
        // NaN (no finite value) travels as CBOR null.
        const auto get = [](const nlohmann::json& v) {
            return v.is_null() ? std::numeric_limits<float>::quiet_NaN() : v.get<float>();
        };
        lines.attributes[a].min = get(ranges[a][0]);
        lines.attributes[a].max = get(ranges[a][1]);
    }
    lines.updateBounds();
    out.polylineIds = vectorOf<std::uint32_t>(header["polylines"]);
    out.tangents = vectorOf<glm::vec3>(header["tangents"]);
    TC_CHECK_OP(out.polylineIds.size(), ==, lines.polylineCount());
    TC_CHECK_OP(out.tangents.size(), ==, lines.polylineCount());
    return out;
}

// Appends `part`'s polylines (with their ids and tangents) to `into`; the attributes must be the
// same (names, order, ranges: every rank's parts carry the whole data's). No LineSet append exists
// in core: the only other concatenation (extractRegionLines) copies runs of one source.
void appendLines(UnpackedLines& into, UnpackedLines&& part) {
    LineSet& a = into.lines;
    const LineSet& b = part.lines;
    if (a.polylineCount() == 0 && a.attributes.empty()) {  // the first part: its attributes' names and ranges
        a.attributes = b.attributes;
        for (Attribute& x : a.attributes) x.values.clear();
        a.velocity = b.velocity;
    }
    TC_CHECK_OP(a.attributes.size(), ==, b.attributes.size());
    const std::uint32_t base = a.offsets.back();
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (std::size_t p = 1; p < b.offsets.size(); ++p) a.offsets.push_back(base + b.offsets[p]);
    for (std::size_t i = 0; i < a.attributes.size(); ++i) {
        TC_CHECK(a.attributes[i].name == b.attributes[i].name);
        a.attributes[i].values.insert(a.attributes[i].values.end(), b.attributes[i].values.begin(),
                                      b.attributes[i].values.end());
    }
    into.polylineIds.insert(into.polylineIds.end(), part.polylineIds.begin(), part.polylineIds.end());
    into.tangents.insert(into.tangents.end(), part.tangents.begin(), part.tangents.end());
}

// A rank's particles as one message: per data frame its particles (extractParticles) and their
// indices in the whole frame (the id AOV's values), in CBOR with the arrays as byte strings.
Bytes packParticles(const ParticleData& data, const std::vector<std::vector<std::uint32_t>>& ids) {
    const auto number = [](float v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); };
    nlohmann::json frames = nlohmann::json::array();
    for (std::size_t f = 0; f < data.frameCount(); ++f) {
        const ParticleSet& p = data.frames[f];
        nlohmann::json j;
        j["positions"] = binaryOf(p.positions);
        j["radii"] = binaryOf(p.radii);
        j["colors"] = binaryOf(p.colors);
        j["radii_from"] = int(p.radiiFrom);
        j["colors_from"] = int(p.colorsFrom);
        j["element_radii"] = p.elementRadii;
        j["attributes"] = nlohmann::json::array();
        for (const Attribute& a : p.attributes)
            j["attributes"].push_back(
                {{"name", a.name}, {"values", binaryOf(a.values)}, {"min", number(a.min)}, {"max", number(a.max)}});
        j["ids"] = binaryOf(ids[f]);
        frames.push_back(std::move(j));
    }
    return nlohmann::json::to_cbor(nlohmann::json{{"frames", std::move(frames)}});
}

// packParticles' message: the particles (bounds of their positions, attribute ranges the whole
// frame's) and per data frame the whole frame's index of each.
ParticleData unpackParticles(const Bytes& bytes, std::vector<std::vector<std::uint32_t>>& ids) {
    const nlohmann::json message = nlohmann::json::from_cbor(bytes);
    const auto number = [](const nlohmann::json& v) {
        return v.is_null() ? std::numeric_limits<float>::quiet_NaN() : v.get<float>();
    };
    ParticleData data;
    ids.clear();
    for (const nlohmann::json& j : message["frames"]) {
        ParticleSet& p = data.frames.emplace_back();
        p.positions = vectorOf<glm::vec3>(j["positions"]);
        p.radii = vectorOf<float>(j["radii"]);
        p.colors = vectorOf<glm::vec4>(j["colors"]);
        p.radiiFrom = Provenance(j["radii_from"].get<int>());
        p.colorsFrom = Provenance(j["colors_from"].get<int>());
        p.elementRadii = j["element_radii"].get<std::map<std::string, float>>();
        for (const nlohmann::json& a : j["attributes"])
            p.attributes.push_back(
                {a["name"].get<std::string>(), vectorOf<float>(a["values"]), number(a["min"]), number(a["max"])});
        for (const glm::vec3& x : p.positions) p.bounds.extend(x);
        p.checkConsistent();
        ids.push_back(vectorOf<std::uint32_t>(j["ids"]));
        TC_CHECK_OP(ids.back().size(), ==, p.size());
    }
    return data;
}

std::string sceneName(const Scene& scene) {
    return scene.file.empty() ? std::string("scene") : scene.file;
}

bool isPartitionInput(const DatasetSpec& d) {
    return d.generate.empty() && !d.trace && !d.path.empty() && isPartitionPath(d.path);
}

bool isPiecedInput(const DatasetSpec& d) {
    return d.generate.empty() && !d.trace && !d.path.empty() && isPiecedVtkFile(d.path);
}

// Per id a frame's technique gives (the share's polyline or particle index), the whole data's;
// nullptr: the ids are the whole data's already.
using GlobalIds = std::function<const std::vector<std::uint32_t>*(int frame)>;

// The frame loop's technique on every rank: the rank's own technique, whose render is a phase
// (a rank that fails fails every rank, before any composite), then IceT's composite into rank 0's
// images in the view's front-to-back order of the regions (region r is rank r's).
class CompositedTechnique final : public Technique {
public:
    CompositedTechnique(std::unique_ptr<Technique> inner, MpiSession& mpi, IcetCompositor& compositor,
                        const KdDecomposition& tree, CompositeMode mode, GlobalIds ids)
        : m_inner(std::move(inner)),
          m_mpi(mpi),
          m_compositor(compositor),
          m_tree(tree),
          m_mode(mode),
          m_ids(std::move(ids)) {}

    void prepareFrame(int frame, StageSink& sink) override {
        m_mpi.phase("prepare frame " + std::to_string(frame), [&] { m_inner->prepareFrame(frame, sink); });
    }

    void render(const FrameSetup& setup, FrameImages& out, StageSink& sink) override {
        m_mpi.phase("render frame " + std::to_string(setup.frame), [&] {
            m_inner->render(setup, out, sink);
            completeBuffers(out, setup.width, setup.height);
            globalIds(setup.frame, out.id);
        });
        const std::vector<int> order = m_tree.viewOrder(setup.camera);
        m_compositor.composite(out, m_mode, order, sink);
    }

    nlohmann::json describe() const override {
        nlohmann::json j = m_inner->describe();
        j["composite"] = m_mode == CompositeMode::Opaque ? "icet z-buffer" : "icet ordered blend";
        return j;
    }

private:
    // IceT composites every buffer; a technique leaves the AOVs nobody asked for unsized (the
    // transparent modes skip their G-buffer pass): background values then, which lose every
    // depth comparison.
    static void completeBuffers(FrameImages& out, int w, int h) {
        const std::size_t n = std::size_t(w) * std::size_t(h);
        out.width = w;
        out.height = h;
        if (out.depth.size() != n) out.depth.assign(n, std::numeric_limits<float>::infinity());
        if (out.normal.size() != 3 * n) out.normal.assign(3 * n, 0.0f);
        if (out.id.size() != n) out.id.assign(n, kBackgroundId);
    }

    // The techniques give the share's polyline (particle) index: the whole data's instead, so
    // that the composited id AOV is what one process gives.
    void globalIds(int frame, std::vector<std::uint32_t>& id) const {
        const std::vector<std::uint32_t>* ids = m_ids ? m_ids(frame) : nullptr;
        if (!ids) return;
        for (std::uint32_t& v : id)
            if (v != kBackgroundId) v = ids->at(v);
    }

    std::unique_ptr<Technique> m_inner;
    MpiSession& m_mpi;
    IcetCompositor& m_compositor;
    const KdDecomposition& m_tree;
    CompositeMode m_mode;
    GlobalIds m_ids;
};

}  // namespace

DataParallel::DataParallel(bool quiet) : m_quiet(quiet) {}

DataParallel::~DataParallel() = default;

void DataParallel::logRoot(const std::string& line) const {
    if (root() && !m_quiet) std::cerr << "tubecast: " << line << "\n";
}

SceneInput DataParallel::loadSceneInput(const std::string& path, const std::vector<std::string>& overrides) {
    SceneInput in;
    if (!isDatasetFile(path)) {
        phase("scene", [&] { in = tc::cli::loadSceneInput(path, overrides); });
        return in;
    }
    // A dataset alone: its default scene depends on the data, which rank 0 alone reads (a
    // partitioned set: only its index, whose bounds and attribute ranges the default needs).
    DatasetLoad load;
    Bytes doc;
    phase("scene", [&] {
        if (!root()) return;
        if (isPartitionPath(path)) {
            const PartitionIndex index = readPartitionIndex(path);
            LineSet summary;
            summary.bounds = index.bounds;
            for (const AttributeRange& a : index.attributes) summary.attributes.push_back({a.name, {}, a.min, a.max});
            doc = nlohmann::json::to_cbor(defaultSceneFor(path, &summary, nullptr));
        } else {
            doc = nlohmann::json::to_cbor(defaultSceneJson(path, load));
        }
    });
    m_mpi.broadcastBytes(doc);
    phase("scene", [&] {
        in.scene = parseScene(nlohmann::json::from_cbor(doc), "", overrides);
        in.scene.file = path;
    });
    if (root() && (load.isParticles() || load.lines.vertexCount())) in.data = std::move(load);
    return in;
}

void DataParallel::sharePlan(OutputPlan& plan) {
    Bytes bytes;
    if (root()) {
        nlohmann::json j;
        j["skipped"] = plan.skipped;
        j["frames"] = nlohmann::json::array();
        for (const FramePlan& p : plan.todo) j["frames"].push_back(p.frame);
        bytes = nlohmann::json::to_cbor(j);
    }
    m_mpi.broadcastBytes(bytes);
    if (root()) return;
    const nlohmann::json j = nlohmann::json::from_cbor(bytes);
    plan.skipped = j["skipped"].get<std::size_t>();
    plan.todo.clear();
    for (const nlohmann::json& f : j["frames"]) plan.todo.push_back({f.get<int>(), {}});
}

RankShare DataParallel::loadPartitionShare(const Scene& scene) {
    // Every rank reads the index and its own brick; bounds are agreed on after styling.
    RankShare share;
    m_inputMode = "partition";
    phase("load", [&] {
        const PartitionIndex index = readPartitionIndex(scene.dataset.path);
        const int ranks = m_mpi.size();
        if (index.regionCount() != ranks)
            throw InputError(index.path + ": regions: the set has " + std::to_string(index.regionCount()) +
                             " regions and the job " + std::to_string(ranks) + " ranks: run with -np " +
                             std::to_string(index.regionCount()) + " or partition again with -n " +
                             std::to_string(ranks));
        m_tree = index.tree;
        m_partitionRadius = index.radius;
        m_partitionIndex = index.path;
        std::vector<RunOrigin> origins;
        share.load.lines = readPartitionRegion(index, m_mpi.rank(), &origins, &share.incomingTangents);
        share.polylineIds = sourcePolylines(origins);
        share.load.source = scene.dataset.path;
        share.source = index.source;
        share.items = index.segments;
        share.dataset = {{"source", scene.dataset.path},
                         {"polylines", index.polylines},
                         {"vertices", index.vertices},
                         {"segments", index.segments},
                         {"skipped", ""}};
    });
    return share;
}

void DataParallel::decomposeLines(const Scene& scene, const LineSet& lines, nlohmann::json& meta,
                                  std::vector<Bytes>& parts) {
    const int ranks = m_mpi.size();
    const StyledLines styled = styleLines(lines, scene.style, scene.file);
    std::vector<float> radii(lines.vertexCount());
    TC_CHECK_OP(styled.vertexCount(), ==, lines.vertexCount());
    // A segment goes to every region its tube, or its halo ring, reaches.
    const float reach = haloReach(scene.style.halo);
    for (std::size_t v = 0; v < radii.size(); ++v) radii[v] = reach * styled.positionRadius[v].w;
    m_tree = KdDecomposition::build(segmentMidpoints(lines), ranks);
    const RegionItems items = assignSegments(m_tree, lines, radii);
    const std::vector<glm::vec3> transported = transportedTangents(lines);
    m_regionCounts = nlohmann::json::array();
    for (int r = 0; r < ranks; ++r) {
        const RegionLines region = extractRegionLines(lines, items[std::size_t(r)]);
        m_regionCounts.push_back({{"assigned_segments", items[std::size_t(r)].size()},
                                  {"owned_segments", ownedSegments(m_tree, r, lines).size()}});
        parts.push_back(packLines(region, incomingTangents(lines, transported, region.origins)));
    }
    meta["tree"] = m_tree.toJson();
    meta["bounds"] = boundsJson(styled.bounds);
    meta["max_radius"] = styled.maxRadius;
    meta["items"] = lines.segmentCount();
}

void DataParallel::decomposeParticles(const Scene& scene, const ParticleData& data, nlohmann::json& meta,
                                      std::vector<Bytes>& parts) {
    const int ranks = m_mpi.size();
    const ParticleSet& first = data.frames.front();
    m_tree = KdDecomposition::build(std::vector<glm::vec3>(first.positions.begin(), first.positions.end()), ranks);
    // Each data frame's particles go to every region their sphere can reach; the largest radius
    // the style or the data can give stands for every sphere's (styling each frame here would
    // cost what the ranks' techniques do again).
    const float radius = particleSeriesMaxRadius(scene, data);
    std::vector<RegionItems> items;  // per data frame
    for (const ParticleSet& f : data.frames) items.push_back(assignParticles(m_tree, f, radius));
    m_regionCounts = nlohmann::json::array();
    for (int r = 0; r < ranks; ++r) {
        std::uint64_t assigned = 0, owned = 0;
        ParticleData region;
        std::vector<std::vector<std::uint32_t>> ids;
        for (std::size_t f = 0; f < data.frameCount(); ++f) {
            ids.push_back(items[f][std::size_t(r)]);
            region.frames.push_back(extractParticles(data.frames[f], ids.back()));
            assigned += ids.back().size();
            owned += ownedParticles(m_tree, r, data.frames[f]).size();
        }
        m_regionCounts.push_back({{"assigned_particles", assigned}, {"owned_particles", owned}});
        parts.push_back(packParticles(region, ids));
    }
    meta["tree"] = m_tree.toJson();
    meta["bounds"] = boundsJson(particleSeriesBounds(scene, data));
    meta["max_radius"] = radius;
    meta["items"] = data.maxParticles();
}

void DataParallel::agreeOnAttributes(const std::string& path, LineSet& lines) {
    // The ranks with polylines read the same point arrays (the file's PPointData); a rank without
    // pieces takes their names, with no values.
    nlohmann::json names = nlohmann::json::array();
    for (const Attribute& a : lines.attributes) names.push_back(a.name);
    const std::vector<nlohmann::json> all = m_mpi.gatherJson({{"names", names}, {"polylines", lines.polylineCount()}});
    Bytes agreed;
    phase("attributes", [&] {
        if (!root()) return;
        std::optional<std::size_t> first;
        for (std::size_t r = 0; r < all.size(); ++r) {
            if (all[r]["polylines"].get<std::uint64_t>() == 0) continue;
            if (!first) first = r;
            if (all[r]["names"] != all[*first]["names"])
                throw InputError(path + ": the pieces of rank " + std::to_string(r) + " hold the point arrays " +
                                 all[r]["names"].dump() + ", those of rank " + std::to_string(*first) + " " +
                                 all[*first]["names"].dump());
        }
        agreed = nlohmann::json::to_cbor(first ? all[*first]["names"] : nlohmann::json::array());
    });
    m_mpi.broadcastBytes(agreed);
    if (lines.polylineCount() == 0) {
        lines.attributes.clear();
        for (const nlohmann::json& n : nlohmann::json::from_cbor(agreed))
            lines.attributes.push_back({n.get<std::string>(), {}});
    }
    // The whole data's range of each attribute (what one process's styling maps colours over):
    // the min of the ranks' minima, the max of their maxima; NaN (no finite value) as +-inf.
    const std::size_t n = lines.attributes.size();
    std::vector<float> lo(n), hi(n);
    const float inf = std::numeric_limits<float>::infinity();
    for (std::size_t a = 0; a < n; ++a) {
        lo[a] = std::isnan(lines.attributes[a].min) ? inf : lines.attributes[a].min;
        hi[a] = std::isnan(lines.attributes[a].max) ? -inf : lines.attributes[a].max;
    }
    MPI_Allreduce(MPI_IN_PLACE, lo.data(), int(n), MPI_FLOAT, MPI_MIN, m_mpi.comm());
    MPI_Allreduce(MPI_IN_PLACE, hi.data(), int(n), MPI_FLOAT, MPI_MAX, m_mpi.comm());
    for (std::size_t a = 0; a < n; ++a) {
        const bool none = lo[a] > hi[a];
        lines.attributes[a].min = none ? std::numeric_limits<float>::quiet_NaN() : lo[a];
        lines.attributes[a].max = none ? std::numeric_limits<float>::quiet_NaN() : hi[a];
    }
}

void DataParallel::buildTreeFromPieces(const LineSet& lines) {
    // Rank 0 builds the tree from every segment's midpoint in rank order, which is file order:
    // the tree a single input's decomposition builds.
    const std::vector<glm::vec3> mine = segmentMidpoints(lines);
    const std::vector<Bytes> all = m_mpi.gatherBytes(std::span<const std::uint8_t>(
        reinterpret_cast<const std::uint8_t*>(mine.data()), mine.size() * sizeof(glm::vec3)));
    Bytes tree;
    phase("decompose", [&] {
        if (!root()) return;
        std::vector<glm::vec3> midpoints;
        for (const Bytes& b : all) {
            const std::size_t at = midpoints.size();
            midpoints.resize(at + b.size() / sizeof(glm::vec3));
            if (!b.empty()) std::memcpy(midpoints.data() + at, b.data(), b.size());
        }
        m_tree = KdDecomposition::build(std::move(midpoints), m_mpi.size());
        tree = nlohmann::json::to_cbor(m_tree.toJson());
    });
    m_mpi.broadcastBytes(tree);
    if (!root()) m_tree = KdDecomposition::fromJson(nlohmann::json::from_cbor(tree), "decomposition");
}

std::vector<Bytes> DataParallel::decomposePiece(const Scene& scene, const LineSet& lines, std::uint64_t first,
                                                std::vector<std::uint64_t>& counts) const {
    // As decomposeLines, on the rank's whole polylines: their tangents and radii are what one
    // process computes; the runs' ids are the whole data's.
    const int ranks = m_mpi.size();
    RegionItems items(static_cast<std::size_t>(ranks));
    std::vector<glm::vec3> transported;
    if (lines.polylineCount() > 0) {
        const StyledLines styled = styleLines(lines, scene.style, scene.file);
        std::vector<float> radii(lines.vertexCount());
        const float reach = haloReach(scene.style.halo);
        for (std::size_t v = 0; v < radii.size(); ++v) radii[v] = reach * styled.positionRadius[v].w;
        items = assignSegments(m_tree, lines, radii);
        transported = transportedTangents(lines);
    }
    std::vector<Bytes> parts;
    counts.assign(2 * std::size_t(ranks), 0);
    for (int r = 0; r < ranks; ++r) {
        RegionLines region = extractRegionLines(lines, items[std::size_t(r)]);
        const std::vector<glm::vec3> tangents = incomingTangents(lines, transported, region.origins);
        for (RunOrigin& o : region.origins) o.polyline += first;
        counts[2 * std::size_t(r)] = items[std::size_t(r)].size();
        counts[2 * std::size_t(r) + 1] = lines.polylineCount() ? ownedSegments(m_tree, r, lines).size() : 0;
        parts.push_back(packLines(region, tangents));
    }
    return parts;
}

RankShare DataParallel::loadPieceShare(const Scene& scene) {
    // Each rank reads its share of the file's pieces (whole polylines, io/line_reader.h), the
    // ranks agree on the attribute ranges, number the polylines as one process does (an exclusive
    // scan of the counts), decompose the segments' midpoints and send each region its segments.
    m_inputMode = "pieces";
    const std::string& path = scene.dataset.path;
    LineSet lines;
    CleanReport cleaned;
    phase("load", [&] { lines = readLinePieces(path, m_mpi.rank(), m_mpi.size(), &cleaned); });
    if (cleaned.any())
        std::cerr << "warning: " << path << " (rank " << m_mpi.rank() << "): " << cleaned.summary() << "\n";
    agreeOnAttributes(path, lines);
    std::uint64_t totals[6] = {lines.polylineCount(),     lines.vertexCount(),       lines.segmentCount(),
                               cleaned.nonFiniteVertices, cleaned.duplicateVertices, cleaned.droppedPolylines};
    std::uint64_t first = 0;
    MPI_Exscan(totals, &first, 1, MPI_UINT64_T, MPI_SUM, m_mpi.comm());
    if (root()) first = 0;  // MPI_Exscan leaves rank 0's result undefined
    MPI_Allreduce(MPI_IN_PLACE, totals, 6, MPI_UINT64_T, MPI_SUM, m_mpi.comm());
    buildTreeFromPieces(lines);
    std::vector<Bytes> parts;
    std::vector<std::uint64_t> counts;
    phase("decompose", [&] { parts = decomposePiece(scene, lines, first, counts); });
    lines = {};
    MPI_Allreduce(MPI_IN_PLACE, counts.data(), int(counts.size()), MPI_UINT64_T, MPI_SUM, m_mpi.comm());
    m_regionCounts = nlohmann::json::array();
    for (std::size_t r = 0; r < counts.size() / 2; ++r)
        m_regionCounts.push_back({{"assigned_segments", counts[2 * r]}, {"owned_segments", counts[2 * r + 1]}});
    const std::vector<Bytes> incoming = m_mpi.exchangeBytes(parts);
    parts.clear();
    RankShare share;
    phase("distribute", [&] {
        const std::string name = path + " (rank " + std::to_string(m_mpi.rank()) + ")";
        UnpackedLines merged;
        for (const Bytes& part : incoming) appendLines(merged, unpackLines(part, name));  // in sender order
        merged.lines.updateBounds();
        share.load.lines = std::move(merged.lines);
        share.polylineIds = std::move(merged.polylineIds);
        share.incomingTangents = std::move(merged.tangents);
        share.load.source = share.source = path;
        share.items = totals[2];
        CleanReport whole;
        whole.nonFiniteVertices = totals[3];
        whole.duplicateVertices = totals[4];
        whole.droppedPolylines = totals[5];
        share.dataset = {{"source", path},
                         {"polylines", totals[0]},
                         {"vertices", totals[1]},
                         {"segments", totals[2]},
                         {"skipped", whole.summary()}};
    });
    return share;
}

RankShare DataParallel::loadShare(const Scene& scene, std::optional<DatasetLoad> preloaded) {
    if (isPartitionInput(scene.dataset)) return loadPartitionShare(scene);
    if (isPiecedInput(scene.dataset)) return loadPieceShare(scene);
    // A single input: rank 0 reads it whole and decomposes it; each rank is sent the segments
    // (particles) that reach its region.
    DatasetLoad whole;
    std::vector<Bytes> parts;
    Bytes meta;
    phase("load", [&] {
        if (!root()) return;
        if (preloaded && preloaded->source == scene.dataset.path && scene.dataset.generate.empty() &&
            !scene.dataset.trace)
            whole = std::move(*preloaded);
        else
            whole = loadDataset(scene.dataset);
        if (whole.cleaned.any()) std::cerr << "warning: " << whole.source << ": " << whole.cleaned.summary() << "\n";
        nlohmann::json m;
        m["source"] = whole.source;
        m["particles"] = whole.isParticles();
        m["dataset"] = datasetSummary(whole);
        if (whole.isParticles())
            decomposeParticles(scene, whole.particles, m, parts);
        else
            decomposeLines(scene, whole.lines, m, parts);
        whole = {};  // rank 0 keeps its share only
        meta = nlohmann::json::to_cbor(m);
    });
    m_mpi.broadcastBytes(meta);
    const nlohmann::json m = nlohmann::json::from_cbor(meta);
    m_inputMode = "scatter";
    const Bytes mine = m_mpi.scatterBytes(parts);
    parts.clear();
    RankShare share;
    phase("distribute", [&] {
        if (!root()) m_tree = KdDecomposition::fromJson(m["tree"], "decomposition");
        share.source = m["source"].get<std::string>();
        share.dataset = m["dataset"];
        const std::string name = share.source + " (rank " + std::to_string(m_mpi.rank()) + ")";
        if (m["particles"].get<bool>()) {
            share.load.particles = unpackParticles(mine, share.particleIds);
        } else {
            UnpackedLines lines = unpackLines(mine, name);
            share.load.lines = std::move(lines.lines);
            share.polylineIds = std::move(lines.polylineIds);
            share.incomingTangents = std::move(lines.tangents);
        }
        share.load.source = share.source;
        share.bounds = boundsOf(m["bounds"]);
        share.maxRadius = m["max_radius"].get<float>();
        share.items = m["items"].get<std::uint64_t>();
    });
    return share;
}

void DataParallel::agreeOnBounds(RankShare& share, const DatasetLoad& mine, const Bounds& localBounds,
                                 float localMaxRadius) {
    share.localEmpty = mine.isParticles() ? mine.particles.maxParticles() == 0 : mine.lines.polylineCount() == 0;
    if (m_inputMode == "scatter") return;
    // A partitioned set or pieces: the union of the ranks' styled bounds is the whole data's:
    // every segment is on some rank,
    // and each bound is a min or max over vertices.
    float lo[4] = {localBounds.lo.x, localBounds.lo.y, localBounds.lo.z, 0.0f};
    float hi[4] = {localBounds.hi.x, localBounds.hi.y, localBounds.hi.z, localMaxRadius};
    MPI_Allreduce(MPI_IN_PLACE, lo, 4, MPI_FLOAT, MPI_MIN, m_mpi.comm());
    MPI_Allreduce(MPI_IN_PLACE, hi, 4, MPI_FLOAT, MPI_MAX, m_mpi.comm());
    share.bounds.lo = {lo[0], lo[1], lo[2]};
    share.bounds.hi = {hi[0], hi[1], hi[2]};
    share.maxRadius = hi[3];
}

void DataParallel::checkShare(const Scene& scene, const RankShare& share) {
    const bool someEmpty = any(share.localEmpty);
    const bool allEmpty = !any(!share.localEmpty);
    phase("check", [&] {
        // With halos the rings reach further than the tubes.
        const float reach = share.maxRadius * haloReach(scene.style.halo);
        if (m_inputMode == "partition" && reach > m_partitionRadius)
            throw InputError(m_partitionIndex + ": radius: the set was partitioned for tubes of radius up to " +
                             std::to_string(m_partitionRadius) + ", the style gives " + std::to_string(reach) +
                             (scene.style.halo.enabled ? " (with the halo ring)" : "") +
                             ": partition again with --radius " + std::to_string(reach));
        // The AO density reduction runs inside the technique, which an empty rank does not make.
        if (scene.render.ao.enabled && someEmpty && !allEmpty)
            throw InputError(sceneName(scene) + ": render.ao: a rank's region holds no data (" +
                             std::to_string(share.items) + " segments for " + std::to_string(m_mpi.size()) +
                             " ranks): use fewer ranks");
    });
}

bool DataParallel::any(bool mine) const {
    int v = mine ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_INT, MPI_MAX, m_mpi.comm());
    return v != 0;
}

void DataParallel::checkScene(const Scene& scene, const TechniqueRegistry& registry) const {
    registry.requireRegions(scene);
    if (scene.render.referenceDepthPeeling || scene.render.referenceRaytraced)
        throw InputError(sceneName(scene) +
                         ": render.reference: not available with --mpi (render the reference "
                         "without --mpi and compare with `tubecast compare`)");
}

void DataParallel::applyRegion(const RankShare& share, TechniqueData& data, TechniqueHooks& hooks) const {
    data.region = m_tree.box(m_mpi.rank());
    data.bounds = share.bounds;
    data.maxRadius = share.maxRadius;
    hooks.reduceDensity = [this](std::vector<float>& grid) { m_mpi.allreduceSum(grid); };
}

std::unique_ptr<Technique> DataParallel::composited(std::unique_ptr<Technique> inner, const Scene& scene,
                                                    const RankShare& share) {
    m_compositor = std::make_unique<IcetCompositor>(m_mpi, scene.image.width, scene.image.height);
    const CompositeMode mode =
        scene.render.transparency == Transparency::Opaque ? CompositeMode::Opaque : CompositeMode::Transparent;
    GlobalIds ids;
    if (!share.polylineIds.empty()) {
        ids = [polylines = share.polylineIds](int) { return &polylines; };
    } else if (!share.particleIds.empty()) {
        // The data frame each animation frame shows (ParticleSeriesTechnique's choice).
        ids = [particles = share.particleIds, pinned = scene.dataset.frame](int frame) {
            return &particles.at(dataFrameFor(particles.size(), frame, pinned));
        };
    }
    return std::make_unique<CompositedTechnique>(std::move(inner), m_mpi, *m_compositor, m_tree, mode, std::move(ids));
}

std::vector<TimingRow> DataParallel::gatherRows(std::vector<TimingRow> mine) const {
    std::vector<TimingRow> all;
    const std::vector<std::vector<TimingRow>> ranks = m_mpi.gatherTimings(mine);
    for (std::size_t r = 0; r < ranks.size(); ++r) {
        for (TimingRow row : ranks[r]) {
            row.rank = int(r);
            all.push_back(std::move(row));
        }
    }
    return all;
}

nlohmann::json DataParallel::manifest(const DatasetLoad& d, std::uint64_t items) const {
    nlohmann::json mine;
    if (d.isParticles()) {
        mine["particles"] = d.particles.maxParticles();
    } else {
        mine["polylines"] = d.lines.polylineCount();
        mine["segments"] = d.lines.segmentCount();
    }
    const std::vector<nlohmann::json> ranks = m_mpi.gatherJson(mine);
    if (!root()) return {};
    nlohmann::json regions = nlohmann::json::array();
    for (int r = 0; r < m_mpi.size(); ++r) {
        nlohmann::json e = ranks[std::size_t(r)];
        e["rank"] = r;
        e["host"] = m_mpi.hosts()[std::size_t(r)];
        e["box"] = boxJson(m_tree.box(r));
        if (m_regionCounts.is_array()) e.update(m_regionCounts[std::size_t(r)]);
        regions.push_back(e);
    }
    return {{"ranks", m_mpi.size()},
            {"hosts", m_mpi.hosts()},
            {"input", m_inputMode},
            {"segments", items},
            {"decomposition", {{"tree", m_tree.toJson()}, {"regions", regions}}}};
}

}  // namespace tc::cli
