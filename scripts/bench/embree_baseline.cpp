// The baseline of tubecast's `raytraced` technique: the small program a user could write on Embree 3
// to render the same line set and view (docs/performance.md, "Ray tracing on the CPU"):
//   embree_baseline SCENE [--frames N] [--set key=value ...] [--ppm FILE]
// The scene, its lines (radii from style.radius, colour and opacity from style) and the cameras of
// the same 30-degree orbit scripts/bench/frame_times.sh renders come from tubecast's scene loading;
// everything timed is plain Embree + oneTBB: round linear curves with neighbour flags, a
// RTC_BUILD_QUALITY_MEDIUM BVH, 8x8 pixel tiles in parallel, headlight Lambert shading into an RGBA8
// buffer (no image file; --ppm writes the last frame after the timing, to look at).
// - opaque (render.transparency "opaque"): one coherent rtcIntersect8 packet per tile row;
// - transparent (any other mode): per pixel, rtcIntersect1 again and again from just behind the
//   last hit, compositing front-facing hits front to back until alpha >= render.raytraced.
//   alpha_cutoff (at most 1 - 1e-6: an exact pass would run to the last hit).
// Prints one line per frame and `median_ms M cpu_ms C hits_per_covered_pixel H` (wall and process
// CPU time) over the frames after the first (as frame_times.sh, whose first frame also warms up).
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "core/animation.h"
#include "core/scene.h"
#include "core/styling.h"
#include "io/dataset.h"

namespace {

constexpr int kTile = 8;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct View {
    glm::vec3 eye, forward, right, up;  // right and up scaled to the image plane at distance 1
    int width, height;
    glm::vec3 dir(int x, int y) const {
        const float u = 2.0f * (float(x) + 0.5f) / float(width) - 1.0f;
        const float v = 1.0f - 2.0f * (float(y) + 0.5f) / float(height);
        return glm::normalize(forward + u * right + v * up);
    }
};

View viewOf(const tc::Camera& c, int width, int height) {
    View v;
    v.eye = c.eye;
    v.forward = glm::normalize(c.target - c.eye);
    const glm::vec3 r = glm::normalize(glm::cross(v.forward, c.up));
    const float tanHalf = std::tan(glm::radians(c.fovYDeg) * 0.5f);
    v.right = r * tanHalf * float(width) / float(height);
    v.up = glm::cross(r, v.forward) * tanHalf;
    v.width = width;
    v.height = height;
    return v;
}

struct Lines {
    std::vector<glm::vec4> color;  // per segment: its first vertex's colour, straight alpha
};

// Headlight Lambert: light from the eye, both sides of the surface lit.
glm::vec3 lambert(const glm::vec4& albedo, const glm::vec3& ng, const glm::vec3& dir) {
    const float len2 = glm::dot(ng, ng);
    const float c = len2 > 0.0f ? std::abs(glm::dot(ng, dir)) / std::sqrt(len2) : 1.0f;
    return glm::vec3(albedo) * (0.2f + 0.8f * c);
}

std::uint32_t pack(const glm::vec4& c) {
    auto b = [](float x) { return std::uint32_t(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f)); };
    return b(c.x) | b(c.y) << 8 | b(c.z) << 16 | b(c.w) << 24;
}

// Calls tile(x0, y0, context, n) for every kTile x kTile tile of the image, tiles in parallel
// (oneTBB), with one intersect context per task (`flags` set) and a hit counter `n` added to `hits`.
template <typename TileFn>
void forEachTile(const View& view, RTCIntersectContextFlags flags, std::atomic<std::uint64_t>& hits, TileFn&& tile) {
    const int tilesX = (view.width + kTile - 1) / kTile, tilesY = (view.height + kTile - 1) / kTile;
    tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY), [&](const tbb::blocked_range<int>& range) {
        std::uint64_t n = 0;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = flags;
        for (int t = range.begin(); t != range.end(); ++t) tile((t % tilesX) * kTile, (t / tilesX) * kTile, context, n);
        hits += n;
    });
}

void renderOpaque(RTCScene scene, const Lines& lines, const View& view, std::uint32_t* image,
                  std::atomic<std::uint64_t>& hits) {
    forEachTile(view, RTC_INTERSECT_CONTEXT_FLAG_COHERENT, hits,
                [&](int x0, int y0, RTCIntersectContext& context, std::uint64_t& n) {
                    for (int y = y0; y < std::min(y0 + kTile, view.height); ++y) {
                        alignas(32) int valid[8];
                        alignas(32) RTCRayHit8 rh;
                        for (int j = 0; j < 8; ++j) {
                            const int x = std::min(x0 + j, view.width - 1);
                            valid[j] = x0 + j < view.width ? -1 : 0;
                            const glm::vec3 d = view.dir(x, y);
                            rh.ray.org_x[j] = view.eye.x, rh.ray.org_y[j] = view.eye.y, rh.ray.org_z[j] = view.eye.z;
                            rh.ray.dir_x[j] = d.x, rh.ray.dir_y[j] = d.y, rh.ray.dir_z[j] = d.z;
                            rh.ray.tnear[j] = 0.0f, rh.ray.tfar[j] = kInf;
                            rh.ray.time[j] = 0.0f, rh.ray.mask[j] = ~0u, rh.ray.id[j] = 0, rh.ray.flags[j] = 0;
                            rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
                            rh.hit.instID[0][j] = RTC_INVALID_GEOMETRY_ID;
                        }
                        rtcIntersect8(valid, scene, &context, &rh);
                        for (int j = 0; j < 8 && x0 + j < view.width; ++j) {
                            glm::vec4 c(0.0f);
                            if (rh.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID) {
                                ++n;
                                const glm::vec3 d(rh.ray.dir_x[j], rh.ray.dir_y[j], rh.ray.dir_z[j]);
                                const glm::vec3 ng(rh.hit.Ng_x[j], rh.hit.Ng_y[j], rh.hit.Ng_z[j]);
                                c = glm::vec4(lambert(lines.color[rh.hit.primID[j]], ng, d), 1.0f);
                            }
                            image[std::size_t(y) * std::size_t(view.width) + std::size_t(x0 + j)] = pack(c);
                        }
                    }
                });
}

void renderTransparent(RTCScene scene, const Lines& lines, const View& view, float cutoff, std::uint32_t* image,
                       std::atomic<std::uint64_t>& hits) {
    forEachTile(view, RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT, hits,
                [&](int x0, int y0, RTCIntersectContext& context, std::uint64_t& n) {
                    for (int y = y0; y < std::min(y0 + kTile, view.height); ++y)
                        for (int x = x0; x < std::min(x0 + kTile, view.width); ++x) {
                            const glm::vec3 d = view.dir(x, y);
                            glm::vec3 color(0.0f);
                            float alpha = 0.0f, tnear = 0.0f;
                            while (alpha < cutoff) {
                                RTCRayHit rh;
                                rh.ray.org_x = view.eye.x, rh.ray.org_y = view.eye.y, rh.ray.org_z = view.eye.z;
                                rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
                                rh.ray.tnear = tnear, rh.ray.tfar = kInf;
                                rh.ray.time = 0.0f, rh.ray.mask = ~0u, rh.ray.id = 0, rh.ray.flags = 0;
                                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                                rtcIntersect1(scene, &context, &rh);
                                if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
                                ++n;
                                const glm::vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
                                if (glm::dot(ng, d) < 0.0f) {  // entering a tube; leaving it adds nothing
                                    const glm::vec4& albedo = lines.color[rh.hit.primID];
                                    const float w = (1.0f - alpha) * albedo.w;
                                    color += w * lambert(albedo, ng, d);
                                    alpha += w;
                                }
                                tnear = std::nextafter(rh.ray.tfar, kInf);
                            }
                            image[std::size_t(y) * std::size_t(view.width) + std::size_t(x)] =
                                pack(glm::vec4(color, alpha));
                        }
                });
}

// CPU time of the process, all threads: on a shared machine a steadier measure of the work than the
// wall clock.
double processCpuMs() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
    using Clock = std::chrono::steady_clock;
    if (argc < 2) {
        std::fprintf(stderr, "usage: embree_baseline SCENE [--frames N] [--set key=value ...] [--ppm FILE]\n");
        return 2;
    }
    int frames = 5;
    std::string ppm;
    std::vector<std::string> overrides;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string a = argv[i], v = argv[i + 1];
        if (a == "--frames")
            frames = std::max(2, std::stoi(v));
        else if (a == "--set")
            overrides.push_back(v);
        else if (a == "--ppm")
            ppm = v;
        else {
            std::fprintf(stderr, "embree_baseline: unknown option %s\n", a.c_str());
            return 2;
        }
    }
    overrides.push_back("animation={\"type\":\"orbit\",\"frames\":" + std::to_string(frames) + ",\"degrees\":30}");
    overrides.push_back("output.name=bench.####");
    tc::Scene scene;
    tc::StyledLines styled;
    try {
        scene = tc::loadScene(argv[1], overrides);
        styled = tc::styleLines(tc::loadDataset(scene.dataset).lines, scene.style, scene.file);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    const bool transparent = scene.render.transparency != tc::Transparency::Opaque;
    const float cutoff = std::min(scene.render.raytracedAlphaCutoff, 1.0f - 1e-6f);

    // Segments s = (v, v + 1) as styleLines lays them out; a segment has a left (right) neighbour
    // when the vertex before v (after v + 1) is on the same polyline.
    const std::size_t segments = styled.segmentCount(), vertices = styled.vertexCount();
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene rtScene = rtcNewScene(device);
    rtcSetSceneBuildQuality(rtScene, RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    auto* v = static_cast<glm::vec4*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, sizeof(glm::vec4), vertices));
    std::copy(styled.positionRadius.begin(), styled.positionRadius.end(), v);
    auto* index = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(std::uint32_t), segments));
    auto* flags = static_cast<std::uint8_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, 1, segments));
    Lines lines;
    lines.color.resize(segments);
    for (std::size_t s = 0; s < segments; ++s) {
        const std::uint32_t a = styled.segmentVertices[2 * s];
        index[s] = a;
        flags[s] = std::uint8_t(
            (a > 0 && styled.polylineId[a - 1] == styled.polylineId[a] ? RTC_CURVE_FLAG_NEIGHBOR_LEFT : 0) |
            (a + 2 < vertices && styled.polylineId[a + 2] == styled.polylineId[a + 1] ? RTC_CURVE_FLAG_NEIGHBOR_RIGHT
                                                                                      : 0));
        lines.color[s] = styled.color[a];
    }
    auto t0 = Clock::now();
    rtcCommitGeometry(geom);
    rtcAttachGeometry(rtScene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(rtScene);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
        std::fprintf(stderr, "error: Embree failed to build the scene\n");
        return 1;
    }
    std::printf("embree_baseline: %zu segments, BVH %.0f ms, %s", segments,
                std::chrono::duration<double, std::milli>(Clock::now() - t0).count(),
                transparent ? "transparent" : "opaque");
    if (transparent) std::printf(", alpha cutoff %g", double(cutoff));
    std::printf("\n");

    const int w = scene.image.width, h = scene.image.height;
    const tc::Camera base = tc::fitCamera(scene.camera, styled.bounds, float(w) / float(h));
    if (base.projection != tc::Projection::Perspective) {
        std::fprintf(stderr, "error: %s: camera: the baseline renders perspective views only\n", argv[1]);
        return 2;
    }
    std::vector<std::uint32_t> image(std::size_t(w) * std::size_t(h));
    std::vector<double> ms, cpuMs;
    double hitsPerPixel = 0;
    for (int f = 0; f < frames; ++f) {
        const View view = viewOf(tc::cameraAtFrame(scene.animation, base, f), w, h);
        std::atomic<std::uint64_t> hits{0};
        const auto start = Clock::now();
        const double cpu0 = processCpuMs();
        if (transparent)
            renderTransparent(rtScene, lines, view, cutoff, image.data(), hits);
        else
            renderOpaque(rtScene, lines, view, image.data(), hits);
        const double frameMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        const double frameCpuMs = processCpuMs() - cpu0;
        const auto covered = std::count_if(image.begin(), image.end(), [](std::uint32_t c) { return c >> 24; });
        const double perPixel = covered ? double(hits.load()) / double(covered) : 0.0;
        std::printf("frame %d: %.1f ms (CPU %.1f ms), %.1f %% covered, %.2f hits per covered pixel\n", f, frameMs,
                    frameCpuMs, 100.0 * double(covered) / double(image.size()), perPixel);
        if (f > 0) ms.push_back(frameMs), cpuMs.push_back(frameCpuMs), hitsPerPixel += perPixel / double(frames - 1);
    }
    std::printf("median_ms %.1f cpu_ms %.1f hits_per_covered_pixel %.2f\n", median(ms), median(cpuMs), hitsPerPixel);
    if (!ppm.empty()) {
        std::ofstream out(ppm, std::ios::binary);
        out << "P6\n" << w << " " << h << "\n255\n";
        for (std::uint32_t c : image) {  // over the white background, as tubecast's images
            const float a = float(c >> 24) / 255.0f;
            for (int k = 0; k < 3; ++k) out.put(char(std::lround(float((c >> (8 * k)) & 255u) + (1.0f - a) * 255.0f)));
        }
    }
    rtcReleaseScene(rtScene);
    rtcReleaseDevice(device);
    return 0;
}
