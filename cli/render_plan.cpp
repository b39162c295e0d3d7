#include "cli/render_plan.h"

#include <filesystem>

#include "core/error.h"

namespace tc::cli {

namespace fs = std::filesystem;

std::string frameBase(const OutputSpec& out, int frame) {
    return (fs::path(out.dir) / frameFileName(out.name, frame)).string();
}

bool frameComplete(const FramePlan& plan, const std::string& hash, std::string* why) {
    for (const auto& p : plan.paths) {
        const OutputCheck c = checkFrameOutput(p, hash);
        if (c.state != OutputState::Complete) {
            if (why) *why = c.reason;
            return false;
        }
    }
    return true;
}

OutputPlan planOutputs(const OutputSpec& out, const PlanRequest& request,
                       const std::function<void(const std::string&)>& note) {
    OutputPlan plan;
    for (int f : request.frames) {
        FramePlan frame{f, {}};
        const std::string base = frameBase(out, f);
        if (out.png) frame.paths.push_back(base + ".png");
        if (out.exr) frame.paths.push_back(base + ".exr");
        std::string firstExisting;
        for (const auto& p : frame.paths)
            if (fs::exists(p) && firstExisting.empty()) firstExisting = p;
        // --resume re-renders a frame unless every output decodes completely and carries this
        // scene's hash (a killed writer cannot leave a truncated final file, but a full disk, a
        // copy or an edit of the scene can).
        if (request.resume && !firstExisting.empty()) {
            std::string why;
            if (frameComplete(frame, request.sceneHash, &why)) {
                ++plan.skipped;
                continue;
            }
            if (note && why != "missing") note("--resume: frame " + std::to_string(f) + " re-rendered: " + why);
        }
        if (!firstExisting.empty() && !request.overwrite && !request.resume)
            throw OutputError(firstExisting +
                              " exists; use --resume to skip finished frames or --overwrite to replace them");
        plan.todo.push_back(frame);
    }
    plan.timingsPath = (fs::path(out.dir) / sideFileName("timings.csv", request.shard)).string();
    plan.runPath = (fs::path(out.dir) / sideFileName("run.json", request.shard)).string();
    plan.qualityPath = (fs::path(out.dir) / sideFileName("quality.csv", request.shard)).string();
    if (request.checkSideFiles && out.timings && !request.overwrite && !request.resume && !plan.todo.empty())
        for (const auto& p : {plan.timingsPath, plan.runPath})
            if (fs::exists(p)) throw OutputError(p + " exists; use --resume to append or --overwrite to replace it");
    return plan;
}

}  // namespace tc::cli
