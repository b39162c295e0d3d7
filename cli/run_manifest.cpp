#include "cli/run_manifest.h"

#include <unistd.h>

#include "gl/context.h"
#include "io/atomic_file.h"
#include "io/dataset.h"
#include "io/json_file.h"

namespace tc::cli {

std::string slurmJobId(const EnvLookup& env) {
    const auto job = env("SLURM_ARRAY_JOB_ID"), task = env("SLURM_ARRAY_TASK_ID");
    if (job && task) return *job + "_" + *task;
    return env("SLURM_JOB_ID").value_or("");
}

RunManifest::RunManifest(const Scene& scene, const std::string& sceneHash) {
    m_json["tubecast_version"] = TUBECAST_VERSION;
    m_json["scene_file"] = scene.file;
    m_json["scene"] = scene.resolved;
    m_json["image"] = {{"width", scene.image.width}, {"height", scene.image.height}};
    m_json["scene_hash"] = sceneHash;
    m_json["host"] = hostName();
    m_json["pid"] = long(getpid());
    const EnvLookup env = processEnv();
    m_json["job_id"] = slurmJobId(env);
    if (auto lp = env("LP_NUM_THREADS")) m_json["lp_num_threads"] = *lp;
}

nlohmann::json datasetSummary(const DatasetLoad& data) {
    return {{"source", data.source},
            {"polylines", data.lines.polylineCount()},
            {"vertices", data.lines.vertexCount()},
            {"segments", data.lines.segmentCount()},
            {"skipped", data.cleaned.summary()}};
}

void RunManifest::setDataset(const nlohmann::json& summary, double loadAndStyleSeconds) {
    m_json["dataset"] = summary;
    m_json["dataset"]["load_and_style_s"] = loadAndStyleSeconds;
}

void RunManifest::setGl(const gl::ContextInfo& info) {
    m_json["gl"] = {{"backend", info.backend},      {"device", info.device},     {"cuda_device", info.cudaDevice},
                    {"vendor", info.vendor},        {"renderer", info.renderer}, {"version", info.version},
                    {"extensions", info.extensions}};
}

void RunManifest::setTechnique(const nlohmann::json& description, const std::string& chosenBecause) {
    m_json["technique"] = description;
    if (!chosenBecause.empty()) m_json["technique_choice"] = chosenBecause;
}

void RunManifest::setFrames(const std::vector<int>& planned, const std::optional<Shard>& shard,
                            const std::string& shardSpec) {
    m_json["frames_planned"] = planned;
    if (shard) m_json["shard"] = {{"index", shard->index}, {"count", shard->count}, {"spec", shardSpec}};
}

void RunManifest::setFirstCamera(const Camera& c) {
    m_json["camera_first_frame"] = {
        {"eye", {c.eye.x, c.eye.y, c.eye.z}},
        {"target", {c.target.x, c.target.y, c.target.z}},
        {"up", {c.up.x, c.up.y, c.up.z}},
        {"fov_deg", c.fovYDeg},
        {"projection", c.projection == Projection::Orthographic ? "orthographic" : "perspective"},
        {"ortho_height", c.orthoHeight}};
}

void RunManifest::setOutcome(const std::vector<int>& rendered, const std::vector<int>& failed,
                             const std::vector<int>& heldElsewhere) {
    m_json["frames_rendered"] = rendered;
    m_json["frames_failed"] = failed;
    m_json["frames_held_elsewhere"] = heldElsewhere;
}

void RunManifest::write(const std::string& path) const {
    writeJsonFile(path, m_json);
}

}  // namespace tc::cli
