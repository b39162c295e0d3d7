#include "io/video_encoder.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

extern char** environ;

namespace tc {

namespace fs = std::filesystem;

namespace {

// A directory removed with its contents when the encode ends, however it ends.
struct TempDir {
    fs::path path;
    ~TempDir() {
        std::error_code ec;
        if (!path.empty()) fs::remove_all(path, ec);
    }
};

std::string shellQuoted(const std::string& s) {
    if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=/.,:%") ==
                          std::string::npos)
        return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// The last `n` lines of a text file (ffmpeg's messages for the error).
std::string tail(const fs::path& path, int n) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) lines.push_back(line);
    std::string out;
    for (std::size_t i = lines.size() > std::size_t(n) ? lines.size() - std::size_t(n) : 0; i < lines.size(); ++i)
        out += (out.empty() ? "" : "; ") + lines[i];
    return out;
}

// Runs argv with stdin from /dev/null and stderr into `errors`; the exit status, or -1.
int run(const std::vector<std::string>& argv, const fs::path& errors) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, argv[0].c_str(), &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) return -1;
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

std::string findFfmpeg() {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "/usr/bin:/bin");
    for (std::string dir; std::getline(dirs, dir, ':');) {
        const fs::path candidate = fs::path(dir.empty() ? "." : dir) / "ffmpeg";
        if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    return "";
}

std::vector<std::string> ffmpegArguments(const std::string& ffmpeg, const VideoEncodeRequest& request,
                                         const std::string& pattern, const std::string& out) {
    const std::string fps = std::to_string(request.fps);
    // yuv420p: the chroma format every player decodes (libx264 would keep 4:4:4 from RGB input);
    // it needs even dimensions, so an odd width or height is padded by one pixel.
    return {ffmpeg,
            "-nostdin",
            "-hide_banner",
            "-loglevel",
            "error",
            "-y",
            "-framerate",
            fps,
            "-start_number",
            "0",
            "-i",
            pattern,
            "-c:v",
            "libx264",
            "-crf",
            std::to_string(request.crf),
            "-pix_fmt",
            "yuv420p",
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-r",
            fps,
            "-movflags",
            "+faststart",
            "-f",
            "mp4",
            out};
}

std::string encodeMp4(const VideoEncodeRequest& request) {
    const std::string& output = request.output;
    auto fail = [&](const std::string& why) -> OutputError {
        return OutputError(output + ": cannot write video: " + why);
    };
    if (request.frames.empty()) throw fail("no frames");
    const std::string ffmpeg = findFfmpeg();
    if (ffmpeg.empty()) throw fail("the ffmpeg program is not on PATH (install the Debian package ffmpeg)");
    const fs::path out = fs::absolute(output);
    std::error_code ec;
    if (!fs::is_directory(out.parent_path(), ec)) throw fail("no such directory " + out.parent_path().string());

    std::string hidden = out.filename().string();  // ".NAME.frames.XXXXXX", hidden next to the movie
    hidden.insert(0, 1, '.');
    hidden.append(".frames.XXXXXX");
    std::string templ = (out.parent_path() / hidden).string();
    if (!mkdtemp(templ.data())) throw fail(std::string("cannot create a temporary directory: ") + std::strerror(errno));
    TempDir temp{templ};
    for (std::size_t i = 0; i < request.frames.size(); ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "%08zu.png", i);
        fs::create_symlink(fs::absolute(request.frames[i]), temp.path / name, ec);
        if (ec) throw fail("cannot link " + request.frames[i] + ": " + ec.message());
    }
    const fs::path partial = temp.path / "movie.mp4";
    const std::vector<std::string> argv =
        ffmpegArguments(ffmpeg, request, (temp.path / "%08d.png").string(), partial.string());
    std::string commandLine;
    for (const std::string& a : argv) {
        if (!commandLine.empty()) commandLine.push_back(' ');
        commandLine.append(shellQuoted(a));
    }
    const fs::path errors = temp.path / "ffmpeg.log";
    const int status = run(argv, errors);
    if (status != 0) {
        const std::string messages = tail(errors, 3);
        throw fail((status < 0 ? "ffmpeg did not run" : "ffmpeg exited with " + std::to_string(status)) +
                   (messages.empty() ? "" : ": " + messages) + " (command: " + commandLine + ")");
    }
    fs::rename(partial, out, ec);
    if (ec) throw fail(ec.message());
    return commandLine;
}

}  // namespace tc
