#include "cli/frame_loop.h"

#include <array>
#include <chrono>
#include <ostream>

#include "cli/batch.h"
#include "cli/frame_writer.h"
#include "core/compositing.h"
#include "core/image_metrics.h"

namespace tc::cli {
namespace {

// Row-major float[16] of a glm matrix as stored (column-major), see ExrOptions::matrices.
std::array<float, 16> matrixValues(const glm::mat4& m) {
    std::array<float, 16> v{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) v[std::size_t(4 * c + r)] = m[c][r];
    return v;
}

// Per-frame EXR header: the OpenEXR standard camera attributes and the render time.
ExrOptions frameExrOptions(const FrameLoopInputs& in, const Camera& camera, double renderSeconds) {
    ExrOptions exr = in.exr;
    const float aspect = float(in.width) / float(in.height);
    const glm::mat4 view = camera.worldToCamera();
    const float far = glm::distance(camera.eye, in.bounds.center()) + in.bounds.radius();
    exr.matrices["worldToCamera"] = matrixValues(view);
    exr.matrices["worldToNDC"] =
        matrixValues(projectionMatrix(camera, aspect, std::max(1e-4f * far, 1e-7f), far) * view);
    exr.floats["tubecast:renderSeconds"] = float(renderSeconds);
    return exr;
}

std::vector<TimingRow> rowsOf(int frame, StageRecorder& timer) {
    std::vector<TimingRow> rows;
    for (const StageTime& st : timer.collect()) rows.push_back({frame, st.stage, st.gpuMs, st.cpuMs, st.items});
    return rows;
}

// The reference technique's image of the same frame, compared into quality.csv; its total time
// becomes the frame's "reference" row.
void renderReference(const FrameLoopInputs& in, const FrameSetup& setup, const FrameImages& images,
                     std::vector<TimingRow>& rows) {
    FrameImages refImages;
    in.reference->render(setup, refImages, *in.referenceTimer);
    double refMs = 0;
    for (const StageTime& st : in.referenceTimer->collect()) refMs += st.cpuMs;
    rows.push_back({setup.frame, "reference", -1.0, refMs, 0});
    const ImageMetrics m = compareRgba(images.rgba, refImages.rgba);
    *in.quality << setup.frame << "," << in.referenceName << "," << m.rmse << "," << m.psnr << "," << m.maxError << "\n"
                << std::flush;
}

// The frame's outputs: composited over the background, the overlay drawn into the PNG's copy of
// the colour (the EXR keeps the rendered colour for later compositing, unless overlay.in_exr).
void writeFrame(const FrameLoopInputs& in, FrameImages& images, const std::vector<std::string>& paths,
                const ExrOptions& exr, int frame, const Camera& camera) {
    compositeUnder(images, in.background);
    FrameImages overlaid;
    const FrameImages* display = &images;
    if (in.overlay && in.overlayInExr) {
        in.overlay(images, frame, camera);
    } else if (in.overlay) {
        overlaid.width = images.width;
        overlaid.height = images.height;
        overlaid.rgba = images.rgba;
        in.overlay(overlaid, frame, camera);
        display = &overlaid;
    }
    // Over an opaque background every alpha is 1 (the overlay blends over it: still 1).
    const PngAlpha alpha = in.background.w >= 1.0f ? PngAlpha::Opaque : PngAlpha::Detect;
    for (const auto& path : paths) {
        if (path.ends_with(".png"))
            writePng(*display, path, in.pngText, kPngFrameZlibLevel, alpha);
        else
            writeExr(images, path, exr);
    }
}

}  // namespace

FrameLoopOutcome runFrameLoop(const std::vector<FramePlan>& todo, const OutputSpec& out, const FrameLoopInputs& in) {
    FrameLoopOutcome outcome;
    FrameWriter writer(in.overlapWrites, in.keepGoing, in.items,
                       {[&](int frame, const std::vector<TimingRow>& rows, double frameMs) {
                            if (in.csv) in.csv->write(rows);
                            outcome.rendered.push_back(frame);
                            in.progress->frameDone(frame, frameMs / 1000.0);
                        },
                        [&](int frame, double seconds, const std::string& error) {
                            outcome.failed.push_back(frame);
                            in.progress->frameFailed(frame, seconds, error);
                        }});
    for (const FramePlan& plan : todo) {
        if (in.placeholders) {
            if (auto holder = in.placeholders->claim(placeholderPath(frameBase(out, plan.frame)))) {
                outcome.heldElsewhere.push_back(plan.frame);
                in.progress->frameSkipped(plan.frame, "being rendered by " + *holder);
                continue;
            }
            // Another process may have finished it between planning and claiming.
            if (in.resume && frameComplete(plan, in.sceneHash)) {
                in.placeholders->release();
                in.progress->frameSkipped(plan.frame, "completed by another process");
                continue;
            }
        }
        const auto frameStart = std::chrono::steady_clock::now();
        try {
            const FrameSetup setup{plan.frame, in.camera(plan.frame), in.width, in.height};
            FrameImages& images = writer.nextImages();
            in.technique->prepareFrame(plan.frame, *in.timer);
            in.technique->render(setup, images, *in.timer);
            const double renderSeconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - frameStart).count();
            std::vector<TimingRow> rows = rowsOf(plan.frame, *in.timer);
            if (in.gatherRows) rows = in.gatherRows(std::move(rows));
            if (in.reference) renderReference(in, setup, images, rows);
            FrameJob job{plan.frame, plan.paths.size(), std::move(rows), frameStart, {}};
            job.write = [&images, &in, paths = plan.paths, exr = frameExrOptions(in, setup.camera, renderSeconds),
                         frame = plan.frame,
                         camera = setup.camera] { writeFrame(in, images, paths, exr, frame, camera); };
            writer.submit(std::move(job));
        } catch (const std::exception& e) {
            // --keep-going: report the frame, write the others. Without it the first failure ends
            // the run with its own exit code, after the write in flight.
            if (!in.keepGoing) {
                writer.flush();
                throw;
            }
            outcome.failed.push_back(plan.frame);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - frameStart).count();
            in.progress->frameFailed(plan.frame, seconds, e.what());
        }
        if (in.placeholders) in.placeholders->release();
    }
    writer.flush();
    return outcome;
}

}  // namespace tc::cli
