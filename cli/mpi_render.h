#pragma once
// `tubecast render --mpi`: one frame rendered by every rank of an MPI job, each rank drawing the
// region of a k-d decomposition (core/kd_decomposition.h) that its share of the data lies in, and
// IceT compositing the ranks' images into rank 0's (cli/icet_compositor.h), which alone writes the
// outputs. The frame loop of one process runs unchanged on every rank; this file supplies what
// differs:
//   - the scene: a dataset given alone is read by rank 0 alone, which sends its default scene;
//   - the plan: rank 0 decides which frames to render (and --resume), every rank renders those;
//   - the data: a single input is read by rank 0, decomposed and each rank's segments sent to it
//     (MpiSession::scatterBytes of .tcb bytes, with the source polyline of each run); a
//     partitioned set (`tubecast partition`, io/partition.h) is read brick by brick, each rank
//     its own (and its runs); a ParaView partitioned file (.pvtp / .pvtu) is read piece by piece,
//     each rank its share of the pieces, and the segments exchanged all-to-all
//     (MpiSession::exchangeBytes) after rank 0 decomposed every rank's midpoints; particles are
//     decomposed by rank 0 as lines are, every data frame;
//   - the technique: made with TechniqueData::region (the rank's box), the whole data's bounds
//     and largest radius, and TechniqueHooks::reduceDensity (the AO grid summed over the ranks),
//     then wrapped so that each frame's render is a phase (a failing rank fails every rank) and
//     ends with the composite in the view's front-to-back region order;
//   - timings: every rank's rows of a frame gathered to rank 0 (timings.csv's rank column);
//   - run.json: the ranks, their hosts and the decomposition.
// Every member function is collective (cli/mpi_session.h) unless it says otherwise.
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli/icet_compositor.h"
#include "cli/mpi_session.h"
#include "cli/render_plan.h"
#include "cli/scene_input.h"
#include "core/kd_decomposition.h"
#include "core/technique.h"
#include "core/technique_registry.h"
#include "io/dataset.h"

namespace tc::cli {

// This rank's share of the data and what every rank agrees on about the whole.
struct RankShare {
    DatasetLoad load;         // this rank's lines (the segments that reach its region), or particles; the
                              // frame loop takes it over
    std::string source;       // the whole dataset's name
    Bounds bounds;            // of the whole styled data (tubes or spheres), the same on every rank
    float maxRadius = 0;      // the whole data's largest radius
    std::uint64_t items = 0;  // the whole data's segments (particles: the largest frame's)
    bool localEmpty = false;  // this rank holds nothing
    nlohmann::json dataset;   // run.json's "dataset" block of the whole data (datasetSummary)
    // Per polyline of `load.lines`, the index of the source polyline it is a run of: the id AOV
    // shows these, as one process does (its ids are the source's polyline indices).
    std::vector<std::uint32_t> polylineIds;
    // Per polyline of `load.lines`: the tangent its source polyline carries into it
    // (StyledLines::incomingTangent), so that the cached AO frames each run as one process does.
    std::vector<glm::vec3> incomingTangents;
    // Particles: per data frame, per particle of the share, its index in the whole data frame.
    std::vector<std::vector<std::uint32_t>> particleIds;
};

class DataParallel {
public:
    // MPI_Init (MpiSession). `quiet`: no log lines from rank 0 either.
    explicit DataParallel(bool quiet);
    ~DataParallel();

    MpiSession& mpi() { return m_mpi; }
    bool root() const { return m_mpi.isRoot(); }

    // `work` as a phase: every rank learns whether any rank failed (then RankFailure on all).
    void phase(std::string_view name, const std::function<void()>& work) { m_mpi.phase(name, work); }

    // loadSceneInput for the job: a dataset given alone is read by rank 0, which sends its default
    // scene to the others (who parse it with the same overrides); a scene file is read by all.
    SceneInput loadSceneInput(const std::string& path, const std::vector<std::string>& overrides);

    // Rank 0's plan (--frames, --shard, --resume) on every rank; the other ranks' frames have no
    // output paths, so they write nothing.
    void sharePlan(OutputPlan& plan);

    // Reads and distributes the data (phases "load" and "distribute"); `preloaded`: the dataset
    // rank 0 read for a default scene. Rank 0 styles a single input of lines whole once, for the
    // radii the assignment must cover and for the bounds every rank uses; particles are assigned
    // by the largest radius any sphere can have (particleSeriesMaxRadius).
    RankShare loadShare(const Scene& scene, std::optional<DatasetLoad> preloaded);
    // After styling the share (its bounds and largest radius): a partitioned set's (pieces') ranks agree on
    // the whole data's bounds and radius; notes whether this rank holds nothing.
    void agreeOnBounds(RankShare& share, const DatasetLoad& mine, const Bounds& localBounds, float localMaxRadius);
    // Checks what needs the whole job (a partition's --radius against the styled radii; ambient
    // occlusion with a rank that holds no data): InputError on every rank (phase "check").
    void checkShare(const Scene& scene, const RankShare& share);

    // True when `mine` is true on any rank.
    bool any(bool mine) const;

    // Before the technique is made: refuses techniques and modes without region support (exit
    // code 2, the list from the registry's descriptors) and render.reference. Not collective.
    void checkScene(const Scene& scene, const TechniqueRegistry& registry) const;
    // The rank's region, the whole data's bounds and radius, and the AO density reduction.
    void applyRegion(const RankShare& share, TechniqueData& data, TechniqueHooks& hooks) const;
    // Collective (IceT's context): `inner` (made with applyRegion's data) wrapped into the
    // technique every rank's frame loop runs: render as a phase, the id AOV turned from the share's
    // indices into the whole data's (share.polylineIds), then the composite.
    std::unique_ptr<Technique> composited(std::unique_ptr<Technique> inner, const Scene& scene, const RankShare& share);
    // A frame's timing rows of every rank on rank 0, each with its rank; none on the others.
    std::vector<TimingRow> gatherRows(std::vector<TimingRow> mine) const;

    // run.json's "mpi": ranks, hosts, the whole data's segments (`items`), the decomposition (boxes,
    // segments per rank), the input mode.
    // Collective (the ranks' counts are gathered); meaningful on rank 0.
    nlohmann::json manifest(const DatasetLoad& mine, std::uint64_t items) const;

private:
    void logRoot(const std::string& line) const;
    // loadShare's parts: a partitioned set's brick; rank 0's decomposition of a single input into
    // the ranks' messages (and `meta`: the tree, the whole data's bounds, largest radius, items).
    RankShare loadPartitionShare(const Scene& scene);
    void decomposeLines(const Scene& scene, const LineSet& lines, nlohmann::json& meta, std::vector<Bytes>& parts);
    // A .pvtp / .pvtu: each rank reads its share of the pieces (loadPieceShare), then the ranks
    // agree on the attributes (names; the whole data's ranges, in `lines`), rank 0 builds the tree
    // from every rank's segment midpoints, and each rank cuts its polylines into the regions'
    // messages (ids from `first`, the whole data's index of its first polyline; `counts`: per
    // region its assigned and owned segments of this rank).
    RankShare loadPieceShare(const Scene& scene);
    void agreeOnAttributes(const std::string& path, LineSet& lines);
    void buildTreeFromPieces(const LineSet& lines);
    std::vector<Bytes> decomposePiece(const Scene& scene, const LineSet& lines, std::uint64_t first,
                                      std::vector<std::uint64_t>& counts) const;
    void decomposeParticles(const Scene& scene, const ParticleData& data, nlohmann::json& meta,
                            std::vector<Bytes>& parts);

    MpiSession m_mpi;
    bool m_quiet;
    KdDecomposition m_tree;
    std::string m_inputMode;        // "scatter", "partition", "pieces"
    float m_partitionRadius = 0;    // a partitioned set's --radius
    std::string m_partitionIndex;   // and its index.json
    nlohmann::json m_regionCounts;  // rank 0, single input: per region what was assigned
    std::unique_ptr<IcetCompositor> m_compositor;
};

}  // namespace tc::cli
