#pragma once
// run.json: what a render run was (docs/outputs.md): the resolved scene and its hash, the dataset,
// the GL context, the technique and why it was chosen, the frames planned and their outcome,
// where and as what it ran. Written once before the first frame (so a killed run still says what
// it was) and again at the end with the outcome.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/batch.h"
#include "core/camera.h"
#include "core/scene.h"

namespace tc {
struct DatasetLoad;
namespace gl {
struct ContextInfo;
}
}  // namespace tc

namespace tc::cli {

// run.json's "dataset" block of a dataset: source, polylines, vertices, segments, what cleaning
// skipped.
nlohmann::json datasetSummary(const DatasetLoad& data);

class RunManifest {
public:
    // Version, scene file and resolved scene, its hash, image size, host, pid, Slurm job and
    // LP_NUM_THREADS (when set).
    RunManifest(const Scene& scene, const std::string& sceneHash);

    // "dataset": datasetSummary of the whole dataset (with --mpi not a rank's share) and the seconds.
    void setDataset(const nlohmann::json& summary, double loadAndStyleSeconds);
    void setGl(const gl::ContextInfo& info);
    // The technique's own description (Technique::describe) and, for render.technique "auto", the
    // log line saying what was chosen and why.
    void setTechnique(const nlohmann::json& description, const std::string& chosenBecause);
    // Where radius, colour and opacity come from (core/style_sources.h).
    void setStyleSources(const std::vector<std::string>& sources) { m_json["style_sources"] = sources; }
    void setFrames(const std::vector<int>& planned, const std::optional<Shard>& shard, const std::string& shardSpec);
    // The camera of the first frame to render (after fit), so other tools can match the view.
    void setFirstCamera(const Camera& camera);
    // `tubecast render --mpi`: "mpi" with the ranks, hosts and decomposition (cli/mpi_render.h).
    void setDataParallel(const nlohmann::json& mpi) { m_json["mpi"] = mpi; }
    void setOutcome(const std::vector<int>& rendered, const std::vector<int>& failed,
                    const std::vector<int>& heldElsewhere);

    const nlohmann::json& json() const { return m_json; }
    // Through io's atomic JSON writer (temp file + rename).
    void write(const std::string& path) const;

private:
    nlohmann::json m_json;
};

// SLURM_JOB_ID, with the array task when there is one ("1234_5"), for placeholders and run.json.
std::string slurmJobId(const EnvLookup& env);

}  // namespace tc::cli
