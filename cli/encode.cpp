// tubecast encode OUT_DIR movie.mp4: the PNG frames of a render, in frame order, as an H.264 MP4.
// Which frames and their names come from the run.json files in OUT_DIR (the scene's frame count
// and output.name) unless --frames / --name say; every one of them must be there.
#include "cli/encode.h"

#include <filesystem>
#include <iostream>
#include <set>

#include "cli/batch.h"
#include "cli/commands.h"
#include "core/animation.h"
#include "core/error.h"
#include "io/json_file.h"
#include "io/video_encoder.h"

namespace tc::cli {

namespace fs = std::filesystem;

std::vector<std::string> framePngs(const std::string& dir, const std::string& pattern, const std::vector<int>& frames) {
    std::vector<std::string> pngs;
    std::vector<int> missing;
    std::string names;
    for (int frame : frames) {
        const fs::path png = fs::path(dir) / (frameFileName(pattern, frame) + ".png");
        std::error_code ec;
        if (fs::is_regular_file(png, ec)) {
            pngs.push_back(png.string());
            continue;
        }
        missing.push_back(frame);
        if (missing.size() <= 10) names += (names.empty() ? "" : ", ") + png.filename().string();
    }
    if (!missing.empty())
        throw InputError(dir + ": " + std::to_string(missing.size()) + " of " + std::to_string(frames.size()) +
                         " frame(s) missing: " + formatFrameList(missing) + " (" + names +
                         (missing.size() > 10 ? ", ..." : "") + ")");
    return pngs;
}

void encodeVideo(const std::vector<std::string>& pngs, const std::string& movie, int fps, int crf, bool quiet) {
    const std::string command = encodeMp4({pngs, movie, fps, crf});
    if (!quiet) {
        std::cerr << "tubecast: encode: " << command << "\n";
        std::cerr << "tubecast: wrote " << movie << " (" << pngs.size() << " frames at " << fps << " fps)\n";
    }
}

std::string videoPath(const OutputSpec& out) {
    TC_CHECK(out.video.has_value());
    const fs::path file(out.video->file);
    return file.is_absolute() ? file.string() : (fs::path(out.dir) / file).string();
}

namespace {

struct EncodeOptions {
    std::string dir, movie, name, frames;
    int fps = 30, crf = 18;
    bool overwrite = false, quiet = false;
};

// The frame list and name pattern of the runs in `dir`: every run*.json there holds the resolved
// scene (sharded runs one each, of one scene).
bool framesFromRuns(const std::string& dir, std::string& pattern, int& frameCount) {
    bool found = false;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (!(name.rfind("run", 0) == 0 && entry.path().extension() == ".json")) continue;
        const nlohmann::json run = readJsonFile(entry.path().string());
        if (!run.contains("scene")) continue;
        Scene scene;
        try {
            scene = parseScene(run["scene"], run.value("scene_file", std::string()));
        } catch (const InputError& e) {
            throw InputError(entry.path().string() + ": the run's scene: " + e.what() +
                             " (give --name and --frames instead)");
        }
        if (found && (scene.output.name != pattern || scene.frameCount() != frameCount))
            throw InputError(entry.path().string() + ": a different scene from the other run files in " + dir +
                             " (give --name and --frames)");
        pattern = scene.output.name;
        frameCount = scene.frameCount();
        found = true;
    }
    return found;
}

void runEncode(const EncodeOptions& o) {
    std::error_code ec;
    if (!fs::is_directory(o.dir, ec)) throw InputError(o.dir + ": no such directory");
    if (fs::path(o.movie).extension() != ".mp4")
        throw InputError(o.movie + ": expected a file name ending in .mp4 (H.264 in MP4)");
    if (fs::exists(o.movie, ec) && !o.overwrite)
        throw OutputError(o.movie + ": exists (use --overwrite to replace it)");
    std::string pattern = "frame.####";
    int frameCount = 0;
    const bool fromRuns = framesFromRuns(o.dir, pattern, frameCount);
    if (!o.name.empty()) pattern = o.name;
    std::vector<int> frames;
    if (!o.frames.empty()) {
        frames = parseFrameList(o.frames, 1 << 30);
    } else if (fromRuns) {
        for (int f = 0; f < frameCount; ++f) frames.push_back(f);
    } else {
        throw InputError(o.dir + ": no run.json: give the frames with --frames (and --name if not \"frame.####\")");
    }
    encodeVideo(framePngs(o.dir, pattern, frames), o.movie, o.fps, o.crf, o.quiet);
}

}  // namespace

void addEncodeCommand(CLI::App& app) {
    auto o = std::make_shared<EncodeOptions>();
    CLI::App* cmd = app.add_subcommand(
        "encode", "Encode a render's PNG frames, in frame order, into an H.264 MP4 (through ffmpeg)");
    cmd->add_option("dir", o->dir, "The render's output directory")->required();
    cmd->add_option("movie", o->movie, "The movie to write (.mp4)")->required();
    cmd->add_option("--fps", o->fps, "Frames per second (default 30)")->check(CLI::Range(1, 240));
    cmd->add_option("--crf", o->crf, "x264 constant rate factor: 0 lossless .. 51; default 18 (visually lossless)")
        ->check(CLI::Range(0, 51));
    cmd->add_option("--name", o->name, "Frame name pattern (default: output.name of the run.json in DIR)");
    cmd->add_option("--frames", o->frames,
                    "Frames to encode: 0..99, 0..99:5, 3,7,12..20 (default: every frame of the run.json's scene)");
    cmd->add_flag("--overwrite", o->overwrite, "Replace an existing movie");
    cmd->add_flag("-q,--quiet", o->quiet, "Do not log the ffmpeg command line");
    cmd->callback([o] { runEncode(*o); });
}

}  // namespace tc::cli
