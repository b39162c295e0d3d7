#pragma once
// Frames to a movie: `tubecast encode OUT_DIR movie.mp4` and output.video at the end of a render
// (an H.264 MP4 through ffmpeg, io/video_encoder.h).
#include <string>
#include <vector>

#include "core/scene.h"

namespace tc::cli {

// The PNG of each of `frames` in `dir` named by the output name `pattern`, in the order given.
// Throws InputError "DIR: N of M frame(s) missing: LIST (NAME, ...)" naming every missing frame.
std::vector<std::string> framePngs(const std::string& dir, const std::string& pattern, const std::vector<int>& frames);

// Encodes `pngs` into `movie` (io/video_encoder.h) and logs the ffmpeg command line used to
// stderr unless `quiet`.
void encodeVideo(const std::vector<std::string>& pngs, const std::string& movie, int fps, int crf, bool quiet);

// output.video of `out` as a path: the file in output.dir unless absolute.
std::string videoPath(const OutputSpec& out);

}  // namespace tc::cli
