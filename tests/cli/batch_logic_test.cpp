// The GL-free batch logic of cli/batch.cpp, tested directly: shard partitioning (I/N and the Slurm
// array variables), side-file names, the scene hash, placeholders and their staleness, merging
// timings, and the llvmpipe thread / CUDA device rules.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <thread>

#include "cli/batch.h"
#include "cli_fixture.h"
#include "core/error.h"
#include "io/atomic_file.h"

namespace fs = std::filesystem;
using namespace tc::cli;

namespace {

EnvLookup envOf(std::map<std::string, std::string> vars) {
    return [vars](const std::string& name) -> std::optional<std::string> {
        auto it = vars.find(name);
        if (it == vars.end()) return std::nullopt;
        return it->second;
    };
}

std::string inputErrorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const tc::InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

// A pid that certainly is not running: a child that has exited and been reaped.
long deadPid() {
    pid_t child = fork();
    if (child == 0) _exit(0);
    int status = 0;
    waitpid(child, &status, 0);
    return long(child);
}

TEST(BatchShard, ShardsPartitionTheFrameListRoundRobin) {
    std::vector<int> frames = {0, 2, 4, 6, 8, 10, 12};  // a --frames 0..12:2 selection
    std::vector<int> all;
    for (int i = 0; i < 3; ++i) {
        std::vector<int> mine = shardFrames(frames, Shard{i, 3});
        for (std::size_t k = 0; k < mine.size(); ++k) EXPECT_EQ(mine[k], frames[std::size_t(i) + 3 * k]);
        all.insert(all.end(), mine.begin(), mine.end());
    }
    std::sort(all.begin(), all.end());
    EXPECT_EQ(all, frames);  // disjoint and complete
    EXPECT_EQ(shardFrames(frames, Shard{1, 3}), (std::vector<int>{2, 8}));
    EXPECT_TRUE(shardFrames({0, 1}, Shard{5, 8}).empty());  // more shards than frames: idle shards
}

TEST(BatchShard, ParsesIOverNAndRejectsBadSpecs) {
    Shard s = parseShard("2/5", envOf({}));
    EXPECT_EQ(s.index, 2);
    EXPECT_EQ(s.count, 5);
    EXPECT_NE(inputErrorOf([] { parseShard("5/5", envOf({})); }).find("--shard 5/5: I must be below N"),
              std::string::npos);
    EXPECT_NE(inputErrorOf([] { parseShard("0/0", envOf({})); }).find("N must be >= 1"), std::string::npos);
    EXPECT_NE(inputErrorOf([] { parseShard("-1/3", envOf({})); }).find("non-negative"), std::string::npos);
    EXPECT_NE(inputErrorOf([] { parseShard("3", envOf({})); }).find("expected I/N"), std::string::npos);
}

TEST(BatchShard, SlurmIndexIsTaskIdMinusMinOverStep) {
    // --array=3-6: ids 3..6, min 3, count 4.
    Shard s = parseShard("slurm", envOf({{"SLURM_ARRAY_TASK_ID", "5"},
                                         {"SLURM_ARRAY_TASK_MIN", "3"},
                                         {"SLURM_ARRAY_TASK_COUNT", "4"},
                                         {"SLURM_ARRAY_TASK_MAX", "6"}}));
    EXPECT_EQ(s.index, 2);
    EXPECT_EQ(s.count, 4);
    // --array=0-12:4: ids 0, 4, 8, 12, step 4, count 4 -> id 8 is shard 2 of 4.
    s = parseShard("slurm", envOf({{"SLURM_ARRAY_TASK_ID", "8"},
                                   {"SLURM_ARRAY_TASK_MIN", "0"},
                                   {"SLURM_ARRAY_TASK_STEP", "4"},
                                   {"SLURM_ARRAY_TASK_COUNT", "4"}}));
    EXPECT_EQ(s.index, 2);
    EXPECT_EQ(s.count, 4);
    // A list array (--array=1,4,9): id 4 is off any constant step from min 1 with count 3.
    EXPECT_NE(
        inputErrorOf([] {
            parseShard(
                "slurm",
                envOf({{"SLURM_ARRAY_TASK_ID", "9"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_COUNT", "3"}}));
        }).find("not as a list"),
        std::string::npos);
    EXPECT_NE(inputErrorOf([] { parseShard("slurm", envOf({})); }).find("SLURM_ARRAY_TASK_ID is not set"),
              std::string::npos);
}

TEST(BatchFiles, SideFilesCarryTheShardAndFrameListsCompress) {
    EXPECT_EQ(sideFileName("timings.csv", Shard{2, 4}), "timings.2-of-4.csv");
    EXPECT_EQ(sideFileName("run.json", Shard{0, 1}), "run.0-of-1.json");
    EXPECT_EQ(sideFileName("quality.csv", std::nullopt), "quality.csv");
    EXPECT_EQ(formatFrameList({7, 3, 5, 6, 3, 10}), "3,5..7,10");
    EXPECT_EQ(formatFrameList({}), "");
    EXPECT_EQ(placeholderPath("out/f.0003"), "out/.f.0003.placeholder");
}

TEST(BatchSceneHash, IgnoresKeyOrderAndOutputPlacementButNotContent) {
    auto a = nlohmann::json::parse(R"({"style": {"radius": 0.02}, "image": {"width": 32},
                                       "output": {"dir": "out", "name": "f.####", "aovs": ["depth"]}})");
    auto b = nlohmann::json::parse(R"({"output": {"aovs": ["depth"], "dir": "elsewhere", "formats": ["png"]},
                                       "description": "same pixels", "image": {"width": 32},
                                       "style": {"radius": 0.02}})");
    EXPECT_EQ(sceneHash(a), sceneHash(b));
    EXPECT_EQ(sceneHash(a).size(), 40u);  // SHA-1 hex
    auto c = a;
    c["style"]["radius"] = 0.03;
    EXPECT_NE(sceneHash(a), sceneHash(c));
    auto d = a;
    d["output"]["aovs"] = {"depth", "normal"};  // other EXR channels
    EXPECT_NE(sceneHash(a), sceneHash(d));
}

TEST(BatchSceneHash, AMovieKeepsTheFramesUnlessItsRateIsInALabel) {
    auto a = nlohmann::json::parse(R"({"image": {"width": 32}, "output": {"dir": "out"}})");
    auto b = a;
    b["output"]["video"] = {{"file", "movie.mp4"}, {"crf", 23}};
    EXPECT_EQ(sceneHash(a), sceneHash(b));  // adding output.video to a finished run re-renders nothing
    // With an overlay the rate is the {time} of labels: 30 (the default) keeps the frames, 24 not.
    a["overlay"] = {{"text", {{{"content", "t = {time}"}}}}};
    b["overlay"] = a["overlay"];
    EXPECT_EQ(sceneHash(a), sceneHash(b));
    b["output"]["video"]["fps"] = 24;
    EXPECT_NE(sceneHash(a), sceneHash(b));
}

TEST(BatchPlaceholders, StaleWhenTheProcessIsGoneOrTheHeartbeatTimedOut) {
    auto alive = [](long pid) { return pid == 100; };
    PlaceholderInfo p{"nodeA", 100, "7_1", 1000.0};
    EXPECT_FALSE(placeholderIsStale(p, 1010.0, 60.0, "nodeA", alive));
    EXPECT_TRUE(placeholderIsStale(p, 1061.0, 60.0, "nodeA", alive));  // alive but silent
    p.pid = 101;
    EXPECT_TRUE(placeholderIsStale(p, 1010.0, 60.0, "nodeA", alive));  // same host, process gone
    // Another host: its pid means nothing here; only the heartbeat counts.
    EXPECT_FALSE(placeholderIsStale(p, 1010.0, 60.0, "nodeB", alive));
    EXPECT_TRUE(placeholderIsStale(p, 1061.0, 60.0, "nodeB", alive));
    EXPECT_TRUE(processAlive(long(getpid())));
    EXPECT_FALSE(processAlive(deadPid()));
}

class BatchPlaceholderFiles : public tc::test::CliFixture {};

TEST_F(BatchPlaceholderFiles, ClaimIsExclusiveAndStaleOnesAreTakenOver) {
    const std::string path = (dir / ".f.0001.placeholder").string();
    {
        Placeholders mine(600.0, "42_0");
        EXPECT_EQ(mine.claim(path), std::nullopt);
        PlaceholderInfo info = placeholderFromJson(tc::test::readText(path), path);
        EXPECT_EQ(info.host, tc::hostName());
        EXPECT_EQ(info.pid, long(getpid()));
        EXPECT_EQ(info.jobId, "42_0");
        // A second claimant (same host, this live process) is refused and told who holds it.
        Placeholders other(600.0, "");
        std::optional<std::string> holder = other.claim(path);
        ASSERT_TRUE(holder.has_value());
        EXPECT_NE(holder->find(tc::hostName() + ":" + std::to_string(getpid())), std::string::npos) << *holder;
        mine.release();
        EXPECT_FALSE(fs::exists(path));
    }
    // Left behind by a process that died on this host: stale, taken over.
    tc::test::writeText(path, toJson(PlaceholderInfo{tc::hostName(), deadPid(), "", unixNow()}).dump());
    {
        Placeholders p(600.0, "");
        EXPECT_EQ(p.claim(path), std::nullopt);
        EXPECT_EQ(placeholderFromJson(tc::test::readText(path), path).pid, long(getpid()));
    }
    EXPECT_FALSE(fs::exists(path));  // the destructor released it
    // Another host's: fresh is respected, an old heartbeat is stale.
    tc::test::writeText(path, toJson(PlaceholderInfo{"other-node", 1, "9", unixNow()}).dump());
    {
        Placeholders p(60.0, "");
        EXPECT_NE(p.claim(path), std::nullopt);
    }
    tc::test::writeText(path, toJson(PlaceholderInfo{"other-node", 1, "9", unixNow() - 61.0}).dump());
    {
        Placeholders p(60.0, "");
        EXPECT_EQ(p.claim(path), std::nullopt);
    }
}

TEST_F(BatchPlaceholderFiles, HeartbeatIsRefreshedWhileHeld) {
    const std::string path = (dir / ".f.0002.placeholder").string();
    Placeholders p(1.0, "");  // heartbeat every 0.25 s
    ASSERT_EQ(p.claim(path), std::nullopt);
    double first = placeholderFromJson(tc::test::readText(path), path).heartbeat;
    double latest = first;
    for (int i = 0; i < 40 && latest <= first; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        latest = placeholderFromJson(tc::test::readText(path), path).heartbeat;
    }
    EXPECT_GT(latest, first);
}

class BatchMerge : public tc::test::CliFixture {};

TEST_F(BatchMerge, ConcatenatesRowsUnderOneHeaderAndRejectsForeignFiles) {
    const std::string h = "frame,stage,gpu_ms,cpu_ms,items\n";
    tc::test::writeText(dir / "timings.0-of-2.csv", h + "0,frame,,1.000,10\n2,frame,,1.500,10\n");
    tc::test::writeText(dir / "timings.1-of-2.csv", h + "1,frame,,2.000,10\n");
    mergeTimings((dir / "all.csv").string(),
                 {(dir / "timings.0-of-2.csv").string(), (dir / "timings.1-of-2.csv").string()});
    EXPECT_EQ(tc::test::readText(dir / "all.csv"), h + "0,frame,,1.000,10\n2,frame,,1.500,10\n1,frame,,2.000,10\n");
    tc::test::writeText(dir / "other.csv", "a,b\n1,2\n");
    std::string err = inputErrorOf([&] { mergeTimings((dir / "x.csv").string(), {(dir / "other.csv").string()}); });
    EXPECT_NE(err.find("other.csv:1: expected the timings header"), std::string::npos) << err;
    tc::test::writeText(dir / "short.csv", h + "1,frame,2.0\n");
    err = inputErrorOf([&] { mergeTimings((dir / "x.csv").string(), {(dir / "short.csv").string()}); });
    EXPECT_NE(err.find("short.csv:2: expected 5 columns"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "x.csv"));
}

TEST(BatchThreads, LlvmpipeThreadsFollowTheJobUnlessTheUserSetThem) {
    EXPECT_EQ(llvmpipeThreads(envOf({{"LP_NUM_THREADS", "7"}, {"SLURM_CPUS_PER_TASK", "2"}}), 4), std::nullopt);
    auto t = llvmpipeThreads(envOf({{"SLURM_CPUS_PER_TASK", "3"}}), 16);
    ASSERT_TRUE(t);
    EXPECT_EQ(t->threads, 3);
    EXPECT_EQ(t->source, "SLURM_CPUS_PER_TASK");
    t = llvmpipeThreads(envOf({}), 2);
    ASSERT_TRUE(t);
    EXPECT_EQ(t->threads, 2);
    EXPECT_EQ(t->source, "affinity mask");
    EXPECT_GE(affinityCpuCount(), 1);
}

TEST(BatchDevices, CudaDeviceComesFromTheVisibleListIndexedByDevice) {
    EXPECT_EQ(cudaDeviceFromEnv(envOf({}), -1), std::nullopt);
    auto c = cudaDeviceFromEnv(envOf({{"CUDA_VISIBLE_DEVICES", "2,3"}, {"SLURM_JOB_GPUS", "5"}}), 1);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->cudaDevice, 3);
    EXPECT_EQ(c->source, "CUDA_VISIBLE_DEVICES=2,3");
    c = cudaDeviceFromEnv(envOf({{"SLURM_JOB_GPUS", "5"}}), -1);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->cudaDevice, 5);
    EXPECT_EQ(cudaDeviceFromEnv(envOf({{"CUDA_VISIBLE_DEVICES", "GPU-1234abcd"}}), -1), std::nullopt);
}

}  // namespace
