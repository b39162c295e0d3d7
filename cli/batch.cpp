#include "cli/batch.h"

#include <OpenImageIO/hash.h>
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/image_io.h"
#include "io/timings_csv.h"

namespace tc::cli {

namespace fs = std::filesystem;

namespace {

// Strict non-negative integer (no sign, no trailing text), bounded so it fits an int.
std::optional<long> parseCount(const std::string& text) {
    if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos)
        return std::nullopt;
    return std::stol(text);
}

std::string readWhole(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

EnvLookup processEnv() {
    return [](const std::string& name) -> std::optional<std::string> {
        const char* v = std::getenv(name.c_str());
        if (!v) return std::nullopt;
        return std::string(v);
    };
}

Shard parseShard(const std::string& spec, const EnvLookup& env) {
    auto fail = [&](const std::string& why) -> void { throw InputError("--shard " + spec + ": " + why); };
    Shard shard;
    if (spec == "slurm") {
        auto need = [&](const char* name) -> long {
            std::optional<std::string> v = env(name);
            if (!v) fail(std::string(name) + " is not set (not running as a Slurm array task? use --shard I/N)");
            std::optional<long> n = parseCount(*v);
            if (!n) fail(std::string(name) + "=" + *v + ": expected a non-negative integer");
            return *n;
        };
        long id = need("SLURM_ARRAY_TASK_ID"), min = need("SLURM_ARRAY_TASK_MIN");
        long count = need("SLURM_ARRAY_TASK_COUNT");
        long step = 1;
        if (env("SLURM_ARRAY_TASK_STEP")) step = need("SLURM_ARRAY_TASK_STEP");
        if (step < 1) fail("SLURM_ARRAY_TASK_STEP must be >= 1");
        if (count < 1) fail("SLURM_ARRAY_TASK_COUNT must be >= 1");
        // --array=A-B:S numbers tasks A, A+S, ...; a list (1,4,9) has no constant step and cannot
        // be mapped to 0..N-1 from these variables alone.
        if (id < min || (id - min) % step != 0 || (id - min) / step >= count)
            fail("task " + std::to_string(id) + " is not on the array's range (min " + std::to_string(min) + ", step " +
                 std::to_string(step) + ", count " + std::to_string(count) +
                 "): submit the array as A-B or A-B:S, not as a list");
        shard.index = int((id - min) / step);
        shard.count = int(count);
        return shard;
    }
    auto slash = spec.find('/');
    if (slash == std::string::npos) fail("expected I/N (0 <= I < N) or \"slurm\"");
    std::optional<long> i = parseCount(spec.substr(0, slash)), n = parseCount(spec.substr(slash + 1));
    if (!i || !n) fail("expected I/N with non-negative integers (0 <= I < N)");
    if (*n < 1) fail("N must be >= 1");
    if (*i >= *n) fail("I must be below N (I is 0-based)");
    shard.index = int(*i);
    shard.count = int(*n);
    return shard;
}

std::vector<int> shardFrames(const std::vector<int>& frames, const Shard& shard) {
    TC_CHECK(shard.count >= 1 && shard.index >= 0 && shard.index < shard.count);
    std::vector<int> mine;
    for (std::size_t k = std::size_t(shard.index); k < frames.size(); k += std::size_t(shard.count))
        mine.push_back(frames[k]);
    return mine;
}

std::string sideFileName(const std::string& name, const std::optional<Shard>& shard) {
    if (!shard) return name;
    auto dot = name.find('.');
    // Appended piecewise: GCC 12 warns (-Wrestrict, a known false positive) on "." + string.
    std::string tag(1, '.');
    tag += std::to_string(shard->index);
    tag += "-of-";
    tag += std::to_string(shard->count);
    if (dot == std::string::npos) return name + tag;
    return name.substr(0, dot) + tag + name.substr(dot);
}

std::string formatFrameList(std::vector<int> frames) {
    std::sort(frames.begin(), frames.end());
    frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
    std::string out;
    for (std::size_t i = 0; i < frames.size();) {
        std::size_t j = i;
        while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
        if (!out.empty()) out += ',';
        out += std::to_string(frames[i]);
        if (j > i) out += ".." + std::to_string(frames[j]);
        i = j + 1;
    }
    return out;
}

std::string sceneHash(const nlohmann::json& resolved) {
    nlohmann::json doc = resolved;
    if (doc.is_object()) {
        doc.erase("description");
        doc.erase("$schema");
        if (doc.contains("output") && doc["output"].is_object()) {
            for (const char* key : {"dir", "name", "formats", "timings"}) doc["output"].erase(key);
            // The movie is made from the frames; its rate reaches them only as the {time} of
            // overlay labels, so with an overlay the rate stays in (as the overlay's).
            nlohmann::json& out = doc["output"];
            nlohmann::json fps = 30;
            if (out.contains("video") && out["video"].is_object()) fps = out["video"].value("fps", fps);
            if (doc.contains("overlay") && doc["overlay"].is_object()) doc["overlay"]["(video fps)"] = fps;
            out.erase("video");
        }
    }
    // nlohmann::json objects are std::map-backed: dump() writes keys sorted, so equal scenes hash
    // equally whatever the key order in the file.
    const std::string text = doc.dump();
    return OIIO::SHA1::digest(text.data(), text.size());
}

OutputCheck checkFrameOutput(const std::string& path, const std::string& hash) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return {OutputState::Missing, "missing"};
    std::map<std::string, std::string> metadata;
    try {
        metadata = verifyImage(path);
    } catch (const Error& e) {
        return {OutputState::Unreadable, e.what()};
    }
    auto it = metadata.find(kSceneHashKey);
    if (it == metadata.end()) return {OutputState::HashMismatch, path + ": no scene hash in its metadata"};
    if (it->second != hash)
        return {OutputState::HashMismatch, path + ": rendered from another scene (hash " + it->second.substr(0, 12) +
                                               ", now " + hash.substr(0, 12) + ")"};
    return {OutputState::Complete, ""};
}

// --- placeholders ---------------------------------------------------------------------------

nlohmann::json toJson(const PlaceholderInfo& info) {
    return {{"host", info.host}, {"pid", info.pid}, {"job_id", info.jobId}, {"heartbeat", info.heartbeat}};
}

PlaceholderInfo placeholderFromJson(const std::string& text, const std::string& path) {
    try {
        nlohmann::json j = nlohmann::json::parse(text);
        PlaceholderInfo info;
        info.host = j.at("host").get<std::string>();
        info.pid = j.at("pid").get<long>();
        info.jobId = j.at("job_id").get<std::string>();
        info.heartbeat = j.at("heartbeat").get<double>();
        return info;
    } catch (const nlohmann::json::exception& e) {
        throw InputError(path + ": not a tubecast placeholder: " + e.what());
    }
}

std::string placeholderPath(const std::string& frameBase) {
    fs::path p(frameBase);
    std::string name(1, '.');
    name += p.filename().string();
    name += ".placeholder";
    return (p.parent_path() / name).string();
}

bool processAlive(long pid) {
    // EPERM: it exists but belongs to someone else.
    return pid > 0 && (kill(pid_t(pid), 0) == 0 || errno == EPERM);
}

double unixNow() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

bool placeholderIsStale(const PlaceholderInfo& info, double now, double timeoutSeconds, const std::string& thisHost,
                        const std::function<bool(long)>& pidAlive) {
    if (info.host == thisHost && !pidAlive(info.pid)) return true;
    return now - info.heartbeat > timeoutSeconds;
}

Placeholders::Placeholders(double timeoutSeconds, std::string jobId)
    : m_timeout(timeoutSeconds), m_jobId(std::move(jobId)), m_host(hostName()) {
    m_thread = std::thread([this] { heartbeatLoop(); });
}

Placeholders::~Placeholders() {
    {
        std::lock_guard lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    m_thread.join();
    release();
}

void Placeholders::writeInfo(const std::string& path, const std::string& tmpSuffix) const {
    PlaceholderInfo info{m_host, long(getpid()), m_jobId, unixNow()};
    std::ofstream out(path + tmpSuffix, std::ios::binary | std::ios::trunc);
    out << toJson(info).dump() << "\n";
    out.close();
    if (!out) throw OutputError(path + ": cannot write placeholder: " + std::strerror(errno));
}

std::optional<std::string> Placeholders::claim(const std::string& path) {
    release();
    const std::string tmp = ".tmp-" + m_host + "-" + std::to_string(getpid());
    for (int attempt = 0; attempt < 3; ++attempt) {
        writeInfo(path, tmp);
        int linked = link((path + tmp).c_str(), path.c_str());
        int linkErrno = errno;
        std::remove((path + tmp).c_str());
        if (linked == 0) {
            std::lock_guard lock(m_mutex);
            m_held = path;
            return std::nullopt;
        }
        if (linkErrno != EEXIST) throw OutputError(path + ": cannot create placeholder: " + std::strerror(linkErrno));
        std::string text = readWhole(path);
        PlaceholderInfo other;
        try {
            other = placeholderFromJson(text, path);
        } catch (const InputError&) {
            // Removed between link() and the read (its frame finished): try again.
            continue;
        }
        if (!placeholderIsStale(other, unixNow(), m_timeout, m_host, processAlive))
            return other.host + ":" + std::to_string(other.pid) +
                   (other.jobId.empty() ? "" : " (job " + other.jobId + ")");
        // Stale: move it aside first. Of several processes that saw it stale, one rename wins;
        // the others get ENOENT and retry link(), which then finds the winner's placeholder.
        const std::string aside = path + ".stale" + tmp;
        if (std::rename(path.c_str(), aside.c_str()) == 0) std::remove(aside.c_str());
    }
    return std::string("another process (contended placeholder)");
}

void Placeholders::release() {
    std::lock_guard lock(m_mutex);
    if (m_held.empty()) return;
    std::remove(m_held.c_str());
    m_held.clear();
}

void Placeholders::heartbeatLoop() {
    const auto interval = std::chrono::duration<double>(std::max(0.25, m_timeout / 4.0));
    std::unique_lock lock(m_mutex);
    while (!m_stop) {
        m_wake.wait_for(lock, interval);
        if (m_stop || m_held.empty()) continue;
        // Rename over our own placeholder: readers see the old or the new one, never a partial one.
        const std::string tmp = ".hb-" + m_host + "-" + std::to_string(getpid());
        try {
            writeInfo(m_held, tmp);
            std::rename((m_held + tmp).c_str(), m_held.c_str());
        } catch (const Error&) {
            // A missed heartbeat only risks another process taking the frame over after the
            // timeout; the render itself must not fail for it.
            std::remove((m_held + tmp).c_str());
        }
    }
}

// --- timings -------------------------------------------------------------------------------

void mergeTimings(const std::string& out, const std::vector<std::string>& inputs) {
    // Every input has the header of the first (a data-parallel render's has a rank column).
    std::string header;
    std::string merged;
    for (const std::string& in : inputs) {
        std::error_code ec;
        if (!fs::exists(in, ec)) throw InputError(in + ": no such file");
        std::ifstream file(in, std::ios::binary);
        if (!file) throw InputError(in + ": cannot read: " + std::strerror(errno));
        std::string line;
        std::size_t lineNo = 0;
        while (std::getline(file, line)) {
            ++lineNo;
            if (!line.empty() && line.back() == '\r') line.pop_back();
            if (lineNo == 1) {
                if (header.empty() && line == kRankTimingsHeader) header = line;
                const std::string expected = header.empty() ? std::string(kTimingsHeader) : header;
                if (line != expected)
                    throw InputError(in + ":1: expected the timings header \"" + expected + "\", got \"" + line + "\"");
                if (header.empty()) header = line;
                continue;
            }
            if (line.empty()) continue;
            // Stage names never contain commas in practice (timings_csv.cpp quotes them if they
            // did); a quoted field would be counted wrong here, so only unquoted rows are checked.
            const auto columns = std::count(header.begin(), header.end(), ',') + 1;
            if (line.find('"') == std::string::npos && std::count(line.begin(), line.end(), ',') + 1 != columns)
                throw InputError(in + ":" + std::to_string(lineNo) + ": expected " + std::to_string(columns) +
                                 " columns, got \"" + line + "\"");
            merged += line;
            merged += '\n';
        }
        if (lineNo == 0) throw InputError(in + ": empty file (no timings header)");
    }
    merged.insert(0, (header.empty() ? std::string(kTimingsHeader) : header) + "\n");
    AtomicFile file(out);
    {
        std::ofstream o(file.tempPath(), std::ios::binary | std::ios::trunc);
        o << merged;
        o.close();
        if (!o) throw OutputError(out + ": cannot write: " + std::strerror(errno));
    }
    file.commit();
}

// --- threads -------------------------------------------------------------------------------

std::optional<ThreadSetting> llvmpipeThreads(const EnvLookup& env, int affinityCpus) {
    if (env("LP_NUM_THREADS")) return std::nullopt;
    if (std::optional<std::string> v = env("SLURM_CPUS_PER_TASK")) {
        std::optional<long> n = parseCount(*v);
        if (n && *n >= 1) return ThreadSetting{int(*n), "SLURM_CPUS_PER_TASK"};
    }
    return ThreadSetting{std::max(1, affinityCpus), "affinity mask"};
}

int affinityCpuCount() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return int(std::max(1L, sysconf(_SC_NPROCESSORS_ONLN)));
    return std::max(1, CPU_COUNT(&set));
}

// --- devices -------------------------------------------------------------------------------

std::optional<CudaDeviceChoice> cudaDeviceFromEnv(const EnvLookup& env, int device) {
    for (const char* name : {"CUDA_VISIBLE_DEVICES", "SLURM_JOB_GPUS"}) {
        std::optional<std::string> v = env(name);
        if (!v || v->empty()) continue;
        std::vector<std::string> entries;
        std::stringstream s(*v);
        for (std::string item; std::getline(s, item, ',');) entries.push_back(item);
        std::size_t k = std::size_t(std::max(device, 0));
        if (k >= entries.size()) return std::nullopt;
        std::optional<long> n = parseCount(entries[k]);
        if (!n) return std::nullopt;  // GPU-UUID or MIG names: no EGL attribute to match them
        return CudaDeviceChoice{int(*n), std::string(name) + "=" + *v};
    }
    return std::nullopt;
}

}  // namespace tc::cli
