#pragma once
// Frames to an H.264 MP4 through the ffmpeg program (libx264): the encoder every video tool
// reads, with none of its API in this process. The frames are linked as a numbered sequence in a
// temporary directory next to the movie, so any frame list (0..99:5, a resumed run's) encodes in
// the order given; the movie is written to a temporary name and renamed when complete.
#include <string>
#include <vector>

namespace tc {

struct VideoEncodeRequest {
    std::vector<std::string> frames;  // PNG files, in display order, all of one size
    std::string output;               // the .mp4 to write (replaced if it exists)
    int fps = 30;
    int crf = 18;  // x264's constant rate factor, 0..51
};

// The ffmpeg found on PATH, or "" when there is none.
std::string findFfmpeg();

// The ffmpeg command line for `request` reading the linked sequence `pattern` and writing `out`,
// as argv.
std::vector<std::string> ffmpegArguments(const std::string& ffmpeg, const VideoEncodeRequest& request,
                                         const std::string& pattern, const std::string& out);

// Encodes; returns the command line it ran (shell-quoted, for the log). Throws OutputError
// "OUTPUT: cannot write video: <reason>" when ffmpeg is missing or fails (with the end of its
// messages) or the movie cannot be written.
std::string encodeMp4(const VideoEncodeRequest& request);

}  // namespace tc
