#pragma once
// Batch rendering at scale (docs/batch.md): shards of a frame list, per-shard side files,
// the scene hash stored in every frame, completeness checks for --resume, placeholders that keep
// parallel jobs on a shared directory from rendering the same frame, merging timings, and the
// llvmpipe thread count from the CPUs a job was given. No OpenGL here: the CLI tests compile
// this file directly and test it without the binary.
#include <condition_variable>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace tc::cli {

// Environment lookup, injectable so the Slurm and thread rules are testable without setenv.
using EnvLookup = std::function<std::optional<std::string>(const std::string&)>;
EnvLookup processEnv();

// A shard of the selected frame list: entries index, index + count, index + 2 count, ...
struct Shard {
    int index = 0;
    int count = 1;
};

// "I/N" (0 <= I < N) or "slurm": I = (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN) /
// SLURM_ARRAY_TASK_STEP (step 1 when unset), N = SLURM_ARRAY_TASK_COUNT. Arrays given as a list
// ("1,4,9") have no constant step and are refused. Throws InputError "--shard SPEC: why".
Shard parseShard(const std::string& spec, const EnvLookup& env);

// The shard's entries of `frames` (in list order).
std::vector<int> shardFrames(const std::vector<int>& frames, const Shard& shard);

// Side file of a process: "timings.csv" -> "timings.2-of-4.csv" under a shard, unchanged without
// one. The extension is everything after the first '.' of the name.
std::string sideFileName(const std::string& name, const std::optional<Shard>& shard);

// The inverse of parseFrameList for messages and re-submit commands: ascending, duplicates
// removed, runs of consecutive frames as "a..b" ("3,5..7").
std::string formatFrameList(std::vector<int> frames);

// Scene hash stored in every frame (EXR header / PNG text chunk "tubecast:sceneHash"): SHA-1 (hex)
// of the resolved scene JSON (after --set) serialised compactly with sorted keys, without the keys
// that do not change pixels: "description", "$schema", output.dir, output.name,
// output.formats, output.timings, output.video (its fps stays in with an overlay: the {time} of
// labels). output.aovs stays in: it changes the EXR's channels.
std::string sceneHash(const nlohmann::json& resolved);
inline constexpr const char* kSceneHashKey = "tubecast:sceneHash";

// Whether an existing frame file counts as done for --resume.
enum class OutputState { Missing, Complete, Unreadable, HashMismatch };
struct OutputCheck {
    OutputState state = OutputState::Missing;
    std::string reason;  // for the log: "truncated: ...", "scene hash abc != def"
};
// Missing when the path does not exist; Unreadable when any pixel fails to decode (truncated,
// empty, a directory, ...); HashMismatch when the file's kSceneHashKey differs from `hash` or is
// absent; else Complete.
OutputCheck checkFrameOutput(const std::string& path, const std::string& hash);

// --- placeholders ---------------------------------------------------------------------------

// What a placeholder file records (JSON): who claimed the frame and when it last proved alive.
struct PlaceholderInfo {
    std::string host;
    long pid = 0;
    std::string jobId;       // SLURM_JOB_ID (with _ARRAY_TASK_ID when in an array), or ""
    double heartbeat = 0.0;  // seconds since the Unix epoch
};
nlohmann::json toJson(const PlaceholderInfo& info);
// Throws InputError when the text is not a placeholder (partly written files never are: they are
// renamed into place complete).
PlaceholderInfo placeholderFromJson(const std::string& text, const std::string& path);

// "out/frame.0003" -> "out/.frame.0003.placeholder".
std::string placeholderPath(const std::string& frameBase);

// Stale = its process is gone (same host, pid not alive) or its heartbeat is older than
// `timeoutSeconds` (any host: the only evidence there is). `pidAlive` is injectable for tests.
bool placeholderIsStale(const PlaceholderInfo& info, double now, double timeoutSeconds, const std::string& thisHost,
                        const std::function<bool(long)>& pidAlive);
bool processAlive(long pid);
double unixNow();

// Claims frames for this process, one at a time. claim() creates the placeholder atomically
// without replacing another process's (a complete temp file hard-linked to the final name: link()
// fails if the name exists, unlike rename()); a stale one is first moved aside by rename, which
// only one of several contenders wins. While a frame is held, a thread refreshes its heartbeat
// every timeout/4 (temp + rename over our own file). release() and the destructor remove it.
class Placeholders {
public:
    Placeholders(double timeoutSeconds, std::string jobId);
    Placeholders(const Placeholders&) = delete;
    Placeholders& operator=(const Placeholders&) = delete;
    ~Placeholders();

    // nullopt when claimed; else who holds it ("host:pid (job J)").
    std::optional<std::string> claim(const std::string& path);
    void release();

private:
    void writeInfo(const std::string& path, const std::string& tmpSuffix) const;
    void heartbeatLoop();

    double m_timeout;
    std::string m_jobId, m_host;
    std::mutex m_mutex;
    std::condition_variable m_wake;
    std::string m_held;
    bool m_stop = false;
    std::thread m_thread;
};

// --- timings -------------------------------------------------------------------------------

// Concatenates timings CSVs (each must start with the header "frame,stage,gpu_ms,cpu_ms,items")
// into `out` with one header, through an AtomicFile. Throws InputError naming the input and line
// for a wrong header or column count.
void mergeTimings(const std::string& out, const std::vector<std::string>& inputs);

// --- threads -------------------------------------------------------------------------------

// LP_NUM_THREADS for llvmpipe: nullopt when the user set it; else the job's CPUs from
// SLURM_CPUS_PER_TASK, else `affinityCpus` (the sched_getaffinity mask), with where it came from.
struct ThreadSetting {
    int threads = 0;
    std::string source;  // "SLURM_CPUS_PER_TASK", "affinity mask"
};
std::optional<ThreadSetting> llvmpipeThreads(const EnvLookup& env, int affinityCpus);
int affinityCpuCount();  // CPUs in this process's affinity mask (>= 1)

// --- devices -------------------------------------------------------------------------------

// The CUDA device a job was given: entry `device` (0 when < 0) of CUDA_VISIBLE_DEVICES, else of
// SLURM_JOB_GPUS; nullopt when neither is set or the entry is not a number (GPU UUIDs). `source`
// names the variable for the log.
struct CudaDeviceChoice {
    int cudaDevice = -1;
    std::string source;
};
std::optional<CudaDeviceChoice> cudaDeviceFromEnv(const EnvLookup& env, int device);

}  // namespace tc::cli
