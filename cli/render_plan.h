#pragma once
// Which frames `tubecast render` renders and which files it writes, decided before any work so a
// conflict costs nothing and nothing is clobbered: every output of every frame of the shard, with
// --resume skipping frames whose outputs decode completely and carry this scene's hash, and the
// per-process side files (timings, run.json, quality). No GL, no rendering.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cli/batch.h"
#include "core/scene.h"

namespace tc::cli {

struct FramePlan {
    int frame = 0;
    std::vector<std::string> paths;  // one per requested format, PNG before EXR
};

struct OutputPlan {
    std::vector<FramePlan> todo;  // in frame-list order
    std::size_t skipped = 0;      // complete already (--resume)
    // Side files of this process: shards sharing a directory never write the same one.
    std::string timingsPath, runPath, qualityPath;
};

struct PlanRequest {
    std::vector<int> frames;  // the frames of this process (after --shard)
    std::optional<Shard> shard;
    std::string sceneHash;  // cli/batch.h sceneHash
    bool resume = false;
    bool overwrite = false;
    bool checkSideFiles = true;  // refuse existing side files without --resume/--overwrite
};

// "out/frame.0007" for output.dir "out", name "frame.####", frame 7.
std::string frameBase(const OutputSpec& out, int frame);

// Whether every output of `plan` is complete for `hash` (--resume); `why` gets the first reason
// it is not.
bool frameComplete(const FramePlan& plan, const std::string& hash, std::string* why = nullptr);

// Plans the outputs of `request.frames` in output.dir (which must exist). Throws OutputError
// naming the first existing output (or side file) when neither --resume nor --overwrite allows
// it. `note` receives --resume's reasons for re-rendering a frame ("frame 3 re-rendered: ...").
OutputPlan planOutputs(const OutputSpec& out, const PlanRequest& request,
                       const std::function<void(const std::string&)>& note = {});

}  // namespace tc::cli
