#pragma once
// The frame loop of `tubecast render`: for each planned frame, claim it (--placeholders), let the
// technique take the frame's data (Technique::prepareFrame), render it, render and compare the
// reference (render.reference -> quality.csv), and hand the images to the frame writer
// (cli/frame_writer.h); --keep-going turns a frame's failure into a report and goes on. Knows no
// GL: techniques come from the registry and time themselves through the StageRecorder given.
#include <functional>
#include <glm/glm.hpp>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "cli/progress.h"
#include "cli/render_plan.h"
#include "core/camera.h"
#include "core/line_set.h"
#include "core/technique.h"
#include "io/image_io.h"
#include "io/timings_csv.h"

namespace tc::cli {

class Placeholders;

struct FrameLoopInputs {
    Technique* technique = nullptr;
    StageRecorder* timer = nullptr;  // the frame's stages (gl::StageTimer with a GL context)
    // render.reference: the exact technique, its timer, its name for quality.csv, and the stream.
    Technique* reference = nullptr;
    StageRecorder* referenceTimer = nullptr;
    std::string referenceName;
    std::ostream* quality = nullptr;

    std::function<Camera(int frame)> camera;  // the animation's camera of a frame
    int width = 0, height = 0;
    Bounds bounds;               // of the data: the far plane of the EXR's worldToNDC
    glm::vec4 background{0.0f};  // image.background (sRGB, straight alpha)
    std::map<std::string, std::string> pngText;
    ExrOptions exr;  // channels and metadata; per-frame camera matrices are added
    // overlay (cli/frame_overlay.h): drawn after the background into the PNG's colour, and into the
    // EXR's only with overlay.in_exr. Null: no overlay (the outputs are exactly the rendered frame).
    std::function<void(FrameImages&, int frame, const Camera&)> overlay;
    bool overlayInExr = false;

    TimingsCsv* csv = nullptr;
    Placeholders* placeholders = nullptr;
    Progress* progress = nullptr;
    std::uint64_t items = 0;  // the dataset's segments (timings "frame" rows)
    // --mpi: a frame's rows of every rank (to rank 0, none on the others); called on every rank
    // after each render. Null: this process's rows.
    std::function<std::vector<TimingRow>(std::vector<TimingRow>)> gatherRows;

    bool keepGoing = false;
    bool overlapWrites = true;
    bool resume = false;  // with placeholders: skip frames another process finished meanwhile
    std::string sceneHash;
};

struct FrameLoopOutcome {
    std::vector<int> rendered, failed, heldElsewhere;
};

// Renders and writes `todo` in order. Without --keep-going the first failure ends the loop with
// its exception (after the write in flight, whose own failure is reported first).
FrameLoopOutcome runFrameLoop(const std::vector<FramePlan>& todo, const OutputSpec& out, const FrameLoopInputs& in);

}  // namespace tc::cli
