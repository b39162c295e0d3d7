// The parts of `tubecast render` tested on their own, without GL: the output plan (which frames
// and files, --resume, --overwrite, side files), run.json, the frame writer pipeline (order,
// overlap, failures) and the frame loop driven by a CPU technique.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "cli/batch.h"
#include "cli/commands.h"
#include "cli/frame_loop.h"
#include "cli/frame_writer.h"
#include "cli/progress.h"
#include "cli/render_plan.h"
#include "cli/run_manifest.h"
#include "cli/technique_registry.h"
#include "cli_fixture.h"
#include "core/error.h"
#include "io/image_io.h"
#include "io/timings_csv.h"

namespace fs = std::filesystem;
using namespace tc;
using namespace tc::cli;

namespace {

class RenderParts : public tc::test::CliFixture {
protected:
    OutputSpec outputs() const {
        OutputSpec out;
        out.dir = (dir / "out").string();
        out.name = "f.####";
        fs::create_directories(out.dir);
        return out;
    }
};

// A frame with one opaque pixel, its PNG carrying `hash` as --resume expects.
void writeCompletePng(const std::string& path, const std::string& hash) {
    FrameImages f;
    f.allocate(2, 2);
    for (float& v : f.rgba) v = 1.0f;
    writePng(f, path, {{kSceneHashKey, hash}});
}

TEST_F(RenderParts, plan_lists_every_output_of_every_frame_and_the_side_files) {
    OutputSpec out = outputs();
    out.exr = true;
    const OutputPlan plan = planOutputs(out, {{0, 4, 8}, Shard{1, 3}, "h", false, false, true});
    ASSERT_EQ(plan.todo.size(), 3u);
    EXPECT_EQ(plan.todo[1].frame, 4);
    EXPECT_EQ(plan.todo[1].paths, (std::vector<std::string>{out.dir + "/f.0004.png", out.dir + "/f.0004.exr"}));
    EXPECT_EQ(plan.timingsPath, out.dir + "/timings.1-of-3.csv");
    EXPECT_EQ(plan.runPath, out.dir + "/run.1-of-3.json");
    EXPECT_EQ(plan.skipped, 0u);
}

TEST_F(RenderParts, plan_refuses_existing_outputs_unless_resumed_or_overwritten) {
    OutputSpec out = outputs();
    out.exr = false;
    writeCompletePng(out.dir + "/f.0001.png", "h");
    try {
        planOutputs(out, {{0, 1, 2}, std::nullopt, "h", false, false, true});
        FAIL() << "no error";
    } catch (const OutputError& e) {
        EXPECT_EQ(std::string(e.what()), out.dir +
                                             "/f.0001.png exists; use --resume to skip finished frames or "
                                             "--overwrite to replace them");
    }
    EXPECT_EQ(planOutputs(out, {{0, 1, 2}, std::nullopt, "h", false, true, true}).todo.size(), 3u);
    // --resume: the complete frame with this scene's hash is skipped; another hash re-renders it.
    const OutputPlan resumed = planOutputs(out, {{0, 1, 2}, std::nullopt, "h", true, false, true});
    EXPECT_EQ(resumed.skipped, 1u);
    ASSERT_EQ(resumed.todo.size(), 2u);
    EXPECT_EQ(resumed.todo[1].frame, 2);
    std::vector<std::string> notes;
    const OutputPlan edited = planOutputs(out, {{1}, std::nullopt, "other", true, false, true},
                                          [&](const std::string& n) { notes.push_back(n); });
    EXPECT_EQ(edited.todo.size(), 1u);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("--resume: frame 1 re-rendered: "), std::string::npos) << notes[0];
}

TEST_F(RenderParts, plan_refuses_side_files_of_an_earlier_run_but_not_for_a_dry_run) {
    OutputSpec out = outputs();
    tc::test::writeText(fs::path(out.dir) / "timings.csv", "frame,stage,gpu_ms,cpu_ms,items\n");
    EXPECT_THROW(planOutputs(out, {{0}, std::nullopt, "h", false, false, true}), OutputError);
    EXPECT_NO_THROW(planOutputs(out, {{0}, std::nullopt, "h", false, false, false}));
    EXPECT_NO_THROW(planOutputs(out, {{0}, std::nullopt, "h", true, false, true}));
}

TEST(RunManifestTest, records_the_choice_the_frames_and_the_outcome) {
    Scene scene;
    scene.file = "scene.json";
    scene.resolved = {{"image", {{"width", 64}}}};
    scene.image.width = 64;
    scene.image.height = 48;
    RunManifest m(scene, "abc");
    m.setTechnique({{"technique", "raytraced"}}, "render.technique auto: raytraced (GL renderer \"llvmpipe\")");
    m.setFrames({0, 2, 4}, Shard{0, 2}, "0/2");
    m.setOutcome({0, 4}, {2}, {});
    const nlohmann::json& j = m.json();
    EXPECT_EQ(j["scene_hash"], "abc");
    EXPECT_EQ(j["scene_file"], "scene.json");
    EXPECT_EQ(j["image"]["height"], 48);
    EXPECT_EQ(j["technique"]["technique"], "raytraced");
    EXPECT_EQ(j["technique_choice"], "render.technique auto: raytraced (GL renderer \"llvmpipe\")");
    EXPECT_EQ(j["frames_planned"], nlohmann::json({0, 2, 4}));
    EXPECT_EQ(j["shard"]["spec"], "0/2");
    EXPECT_EQ(j["frames_failed"], nlohmann::json({2}));
    EXPECT_EQ(j["tubecast_version"], TUBECAST_VERSION);
    EXPECT_EQ(j["pid"], long(getpid()));
}

TEST(RunManifestTest, slurm_job_ids_carry_the_array_task) {
    auto env = [](std::map<std::string, std::string> vars) -> EnvLookup {
        return [vars](const std::string& k) -> std::optional<std::string> {
            auto it = vars.find(k);
            return it == vars.end() ? std::nullopt : std::optional<std::string>(it->second);
        };
    };
    EXPECT_EQ(slurmJobId(env({{"SLURM_JOB_ID", "77"}})), "77");
    EXPECT_EQ(slurmJobId(env({{"SLURM_JOB_ID", "78"}, {"SLURM_ARRAY_JOB_ID", "70"}, {"SLURM_ARRAY_TASK_ID", "3"}})),
              "70_3");
    EXPECT_EQ(slurmJobId(env({})), "");
}

// The writer reports frames in submission order with their write, frame and interval rows,
// whether the writes overlap the next render or not.
TEST(FrameWriterTest, reports_frames_in_order_with_the_write_rows) {
    for (bool overlap : {false, true}) {
        SCOPED_TRACE(overlap);
        std::vector<int> done;
        std::vector<std::vector<TimingRow>> rows;
        std::vector<int> written;
        {
            FrameWriter w(overlap, false, 123,
                          {[&](int f, const std::vector<TimingRow>& r, double) {
                               done.push_back(f);
                               rows.push_back(r);
                           },
                           {}});
            for (int f = 0; f < 4; ++f) {
                FrameImages& images = w.nextImages();
                images.allocate(1, 1);
                FrameJob job{f, 2, {{f, "render", -1.0, 1.0, 0}}, std::chrono::steady_clock::now(), {}};
                job.write = [&written, f] { written.push_back(f); };
                w.submit(std::move(job));
                // With overlap, at most the last frame is still in flight.
                EXPECT_GE(int(done.size()), overlap ? f : f + 1);
            }
            w.flush();
        }
        EXPECT_EQ(done, (std::vector<int>{0, 1, 2, 3}));
        EXPECT_EQ(written, (std::vector<int>{0, 1, 2, 3}));
        ASSERT_EQ(rows[2].size(), 4u);
        EXPECT_EQ(rows[2][0].stage, "render");
        EXPECT_EQ(rows[2][1].stage, "write");
        EXPECT_EQ(rows[2][1].items, 2u);
        EXPECT_EQ(rows[2][2].stage, "frame");
        EXPECT_EQ(rows[2][2].items, 123u);
        EXPECT_EQ(rows[2][3].stage, "frame_interval");
    }
}

TEST(FrameWriterTest, overlapping_writes_alternate_two_buffers) {
    FrameWriter serial(false, false, 0, {});
    EXPECT_EQ(&serial.nextImages(), &serial.nextImages());
    FrameWriter overlapped(true, false, 0, {});
    FrameImages* a = &overlapped.nextImages();
    FrameImages* b = &overlapped.nextImages();
    EXPECT_NE(a, b);
    EXPECT_EQ(&overlapped.nextImages(), a);
}

TEST(FrameWriterTest, a_failed_write_propagates_or_is_reported_with_keep_going) {
    for (bool overlap : {false, true}) {
        SCOPED_TRACE(overlap);
        auto failing = [](int f) {
            FrameJob job{f, 1, {}, std::chrono::steady_clock::now(), {}};
            job.write = [f] {
                if (f == 1) throw OutputError("disk full");
            };
            return job;
        };
        FrameWriter strict(overlap, false, 0, {});
        strict.submit(failing(0));
        EXPECT_THROW(
            {
                strict.submit(failing(1));
                strict.flush();
            },
            OutputError);

        std::vector<int> done, failed;
        std::string error;
        FrameWriter lenient(overlap, true, 0,
                            {[&](int f, const std::vector<TimingRow>&, double) { done.push_back(f); },
                             [&](int f, double, const std::string& e) {
                                 failed.push_back(f);
                                 error = e;
                             }});
        for (int f = 0; f < 3; ++f) lenient.submit(failing(f));
        lenient.flush();
        EXPECT_EQ(done, (std::vector<int>{0, 2}));
        EXPECT_EQ(failed, (std::vector<int>{1}));
        EXPECT_EQ(error, "disk full");
    }
}

// A CPU technique: one colour per frame, a stage per call, and a failure on request.
class StubTechnique final : public Technique {
public:
    std::vector<int> prepared, rendered;
    int failOn = -1;
    void prepareFrame(int frame, StageSink& sink) override {
        sink.begin("upload");
        sink.end();
        prepared.push_back(frame);
    }
    void render(const FrameSetup& setup, FrameImages& out, StageSink& sink) override {
        if (setup.frame == failOn) throw InputError("frame " + std::to_string(setup.frame) + " is cursed");
        sink.begin("stub");
        out.allocate(setup.width, setup.height);
        for (std::size_t i = 0; i < out.pixelCount(); ++i) {
            out.rgba[4 * i + 0] = float(setup.frame) / 4.0f;
            out.rgba[4 * i + 3] = 1.0f;
        }
        sink.setItems(std::uint64_t(setup.frame));
        sink.end();
        rendered.push_back(setup.frame);
    }
    nlohmann::json describe() const override { return {{"technique", "stub"}}; }
};

struct LoopRun {
    FrameLoopOutcome outcome;
    std::string csv;
};

LoopRun runLoop(const fs::path& dir, StubTechnique& technique, bool keepGoing, bool overlap) {
    OutputSpec out;
    out.dir = (dir / "out").string();
    out.name = "f.####";
    out.exr = false;
    fs::create_directories(out.dir);
    const OutputPlan plan = planOutputs(out, {{0, 1, 2}, std::nullopt, "h", false, true, true});
    CpuStageTimer timer;
    std::ostringstream err, log;
    Progress progress(plan.todo.size(), true, false, err, log, false);
    LoopRun run;
    {
        TimingsCsv csv(plan.timingsPath, false);
        FrameLoopInputs in;
        in.technique = &technique;
        in.timer = &timer;
        in.camera = [](int) { return Camera{}; };
        in.width = 8;
        in.height = 6;
        in.csv = &csv;
        in.progress = &progress;
        in.items = 99;
        in.keepGoing = keepGoing;
        in.overlapWrites = overlap;
        in.pngText = {{kSceneHashKey, "h"}};
        run.outcome = runFrameLoop(plan.todo, out, in);
    }
    run.csv = tc::test::readText(plan.timingsPath);
    return run;
}

TEST_F(RenderParts, the_loop_prepares_renders_and_writes_every_frame_in_order) {
    for (bool overlap : {false, true}) {
        SCOPED_TRACE(overlap);
        StubTechnique technique;
        const LoopRun run = runLoop(dir, technique, false, overlap);
        EXPECT_EQ(technique.prepared, (std::vector<int>{0, 1, 2}));
        EXPECT_EQ(run.outcome.rendered, (std::vector<int>{0, 1, 2}));
        EXPECT_TRUE(run.outcome.failed.empty());
        for (int f = 0; f < 3; ++f) {
            const std::string path = (dir / "out" / ("f.000" + std::to_string(f) + ".png")).string();
            EXPECT_EQ(checkFrameOutput(path, "h").state, OutputState::Complete) << path;
        }
        // One frame's rows in stage order, frames in order: upload, stub, write, frame, frame_interval.
        EXPECT_NE(run.csv.find("1,upload,"), std::string::npos) << run.csv;
        EXPECT_LT(run.csv.find("0,frame_interval"), run.csv.find("1,upload"));
        EXPECT_LT(run.csv.find("1,stub,,"), run.csv.find("1,write,"));
        EXPECT_NE(run.csv.find(",99\n"), std::string::npos) << "frame rows carry the segment count";
    }
}

TEST_F(RenderParts, the_loop_reports_a_failed_frame_and_goes_on_with_keep_going) {
    StubTechnique technique;
    technique.failOn = 1;
    const LoopRun run = runLoop(dir, technique, true, true);
    EXPECT_EQ(run.outcome.rendered, (std::vector<int>{0, 2}));
    EXPECT_EQ(run.outcome.failed, (std::vector<int>{1}));
    EXPECT_FALSE(fs::exists(dir / "out" / "f.0001.png"));
    EXPECT_TRUE(fs::exists(dir / "out" / "f.0002.png"));

    StubTechnique strict;
    strict.failOn = 1;
    EXPECT_THROW(runLoop(dir, strict, false, true), InputError);
    EXPECT_TRUE(fs::exists(dir / "out" / "f.0000.png")) << "the frame before the failure is written";
    EXPECT_TRUE(strict.rendered == std::vector<int>{0});
}

TEST(ProgressTest, json_events_go_to_stdout_and_failures_are_never_silenced) {
    std::ostringstream err, out;
    Progress json(2, true, true, err, out, false);
    json.event({{"event", "start"}});
    json.frameDone(0, 0.5);
    json.frameFailed(1, 0.25, "bad");
    std::istringstream lines(out.str());
    std::string line;
    std::vector<nlohmann::json> events;
    while (std::getline(lines, line)) events.push_back(nlohmann::json::parse(line));
    ASSERT_EQ(events.size(), 3u);
    EXPECT_EQ(events[1]["event"], "frame");
    EXPECT_EQ(events[1]["done"], 1);
    EXPECT_EQ(events[2]["event"], "failed");
    EXPECT_EQ(events[2]["error"], "bad");

    std::ostringstream err2, out2;
    Progress quiet(1, true, false, err2, out2, false);
    quiet.frameDone(0, 1.0);
    quiet.frameFailed(1, 1.0, "broken");
    EXPECT_EQ(err2.str(), "error: frame 1: broken\n");
    EXPECT_EQ(formatSeconds(75), "1 min 15 s");
}

TEST(TechniquesCommand, markdown_lists_every_registered_technique) {
    const std::string md = techniquesMarkdown(techniqueRegistry());
    for (const TechniqueDescriptor& d : techniqueRegistry().all())
        EXPECT_NE(md.find("| `" + d.name + "` |"), std::string::npos) << d.name;
}

}  // namespace

namespace {

TEST(TechniquesCommand, the_readme_table_is_the_markdown_output) {
    const std::string readme = tc::test::readText(fs::path(TUBECAST_SOURCE_DIR) / "README.md");
    const std::string begin = "<!-- techniques:begin -->\n", end = "<!-- techniques:end -->";
    const std::size_t a = readme.find(begin), b = readme.find(end);
    ASSERT_NE(a, std::string::npos);
    ASSERT_NE(b, std::string::npos);
    EXPECT_EQ(readme.substr(a + begin.size(), b - a - begin.size()), techniquesMarkdown(techniqueRegistry()))
        << "README.md's table: paste `tubecast techniques --markdown` between the markers";
}

}  // namespace
