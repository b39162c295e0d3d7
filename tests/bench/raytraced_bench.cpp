// Benchmark of the ray tracer's frame, stage by stage, in ONE process so the variants are
// measured back to back on the same BVH (the machine is shared; ratios are what survive load):
//   raytrace per traversal mode (rtcIntersect1 / rtcIntersect8 / rtcIntersect1M), then the output
//   path of the frame loop: compositeUnder and writePng at the given zlib levels.
//   tubecast_raytraced_bench SCENE [--frames N] [--set key=value ...] [--modes single,packet8,packet16,stream]
//                            [--hits-per-pass 1,4,16] [--png-levels 6,1] [--png-dir DIR]
// Prints per-variant medians over the frames (wall ms) and the PNG sizes. --hits-per-pass (transparent
// scenes): the raytrace variants again per number of hits collected per traversal (0 = the default),
// with the Embree hits per covered pixel.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/animation.h"
#include "core/compositing.h"
#include "core/scene.h"
#include "core/styling.h"
#include "io/dataset.h"
#include "io/image_io.h"
#include "rt/raytraced_renderer.h"

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// CPU time of the whole process (all threads): on a shared machine the wall clock mostly measures
// the other processes; CPU ms say what the work costs (x 1/threads on an idle machine for the
// parallel stages).
double processCpuMs() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string item; std::getline(in, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace tc;
    if (argc < 2) {
        std::cerr << "usage: tubecast_raytraced_bench SCENE [--frames N] [--set k=v ...] [--modes "
                     "single,packet8,packet16,stream]"
                     " [--hits-per-pass 1,4,16] [--png-levels 6,1] [--png-dir DIR]\n";
        return 2;
    }
    std::vector<std::string> overrides{"render.technique=raytraced", "output.name=bench.####"};
    int frames = 3;
    std::vector<std::string> modes{"single", "packet8", "stream"};
    std::vector<std::string> pngLevels{"6", "1"};
    std::vector<std::string> hitsPerPass{"0"};
    std::string pngDir = std::filesystem::temp_directory_path() / "tubecast_raytraced_bench";
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--frames")
            frames = std::stoi(v);
        else if (a == "--set")
            overrides.push_back(v);
        else if (a == "--modes")
            modes = split(v);
        else if (a == "--hits-per-pass")
            hitsPerPass = split(v);
        else if (a == "--png-levels")
            pngLevels = split(v);
        else if (a == "--png-dir")
            pngDir = v;
        else {
            std::cerr << "unknown option " << a << "\n";
            return 2;
        }
    }
    std::filesystem::create_directories(pngDir);

    // A 30-degree orbit as scripts/bench/frame_times.sh, so frames differ.
    overrides.push_back("animation={\"type\":\"orbit\",\"frames\":" + std::to_string(std::max(frames, 2)) +
                        ",\"degrees\":30}");
    const Scene scene = loadScene(argv[1], overrides);
    auto t0 = Clock::now();
    const DatasetLoad data = loadDataset(scene.dataset);
    const StyledLines lines = styleLines(data.lines, scene.style, scene.file);
    std::printf("dataset: %zu segments (%.0f ms)\n", lines.segmentCount(), msSince(t0));
    t0 = Clock::now();
    auto renderer = rt::RaytracedRenderer::create(scene, lines);
    std::printf("create (BVH build%s): %.0f ms\n", scene.render.ao.enabled ? " + AO data" : "", msSince(t0));

    const int w = scene.image.width, h = scene.image.height;
    const Camera base = fitCamera(scene.camera, lines.bounds, float(w) / float(h));
    const std::map<std::string, rt::Traversal> byName{{"single", rt::Traversal::Single},
                                                      {"packet8", rt::Traversal::Packet8},
                                                      {"packet16", rt::Traversal::Packet16},
                                                      {"stream", rt::Traversal::Stream}};
    std::map<std::string, std::vector<double>> ms, cpu;
    std::map<std::string, std::uintmax_t> bytes;
    std::map<std::string, double> hitsPerPixel;
    FrameImages images;
    for (int f = 0; f < frames; ++f) {
        const Camera camera = cameraAtFrame(scene.animation, base, f);
        for (const auto& mode : modes)
            for (const auto& k : hitsPerPass) {
                renderer->setTraversal(byName.at(mode));
                renderer->setHitsPerPass(std::stoi(k));
                const std::string name = "raytrace " + mode + (k == "0" ? "" : " K=" + k);
                tc::CpuStageTimer timer;
                const double c0 = processCpuMs();
                renderer->render(camera, w, h, images, timer);
                ms[name].push_back(timer.totalMs());
                cpu[name].push_back(processCpuMs() - c0);
                std::size_t covered = 0;
                for (std::size_t i = 0; i < images.pixelCount(); ++i) covered += images.rgba[4 * i + 3] > 0.0f;
                hitsPerPixel[name] = covered ? double(renderer->lastHitCount()) / double(covered) : 0.0;
            }
        auto t1 = Clock::now();
        double c1 = processCpuMs();
        compositeUnder(images, scene.image.background);
        ms["compositeUnder"].push_back(msSince(t1));
        cpu["compositeUnder"].push_back(processCpuMs() - c1);
        for (const auto& level : pngLevels) {
            const std::string path = pngDir + "/frame_z" + level + ".png";
            auto p0 = Clock::now();
            const double c2 = processCpuMs();
            writePng(images, path, {}, std::stoi(level));
            ms["writePng level " + level].push_back(msSince(p0));
            cpu["writePng level " + level].push_back(processCpuMs() - c2);
            bytes["writePng level " + level] = std::filesystem::file_size(path);
        }
    }
    std::printf(
        "| variant | wall ms (median of %d) | CPU ms, all threads (median) | wall ms per frame | output |\n"
        "|---|---|---|---|---|\n",
        frames);
    for (const auto& [name, v] : ms) {
        std::ostringstream all;
        for (double x : v) all << (all.tellp() > 0 ? " " : "") << int(x + 0.5);
        std::string size = bytes.count(name) ? std::to_string(bytes[name] / 1024) + " KiB" : "";
        if (hitsPerPixel.count(name)) size = std::to_string(hitsPerPixel[name]) + " hits per covered pixel";
        std::printf("| %s | %.1f | %.1f | %s | %s |\n", name.c_str(), median(v), median(cpu[name]), all.str().c_str(),
                    size.c_str());
    }
    return 0;
}
