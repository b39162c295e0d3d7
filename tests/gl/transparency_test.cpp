// The transparent paths (gl/transparent_renderer.cpp: object order, k-buffer, depth peeling) against
// their ground truths: depth peeling against the CPU reference compositor
// (core/transparent_reference.h), the k-buffer and object order against depth peeling, and cap
// clipping (Groß & Gumhold 2020, Sect. 5.4) against analytic tubes and the CPU reference.
//
// Every path shades the same fragments (shaders/transparent_fragment.glsl: one per segment entry
// after cap clipping, colour clamped to [0, 1]) and blends them "under" in fp32 into an RGBA32F
// target; they differ only in the order fragments are blended and in the k-buffer's RGBA8
// storage. The tolerances below follow from that; each says why.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image_metrics.h"
#include "core/rounded_cone.h"
#include "core/scene.h"
#include "core/technique.h"
#include "core/transparent_reference.h"
#include "gl/gpu_timer.h"
#include "gl/techniques.h"
#include "gl/transparent_renderer.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

// --- Tolerances ------------------------------------------------------------------------------

// CPU reference vs depth peeling, colour (linear, premultiplied), absolute, on pixels whose CPU
// fragment set is the same in their whole 3x3 neighbourhood. Both sides cast the same rays
// through the same intersector and shading, and accumulate "under" in fp32; the differences are
// llvmpipe's contracted multiply-adds and pow/rsqrt approximations and the blend's
// (1 - A) * (a c) vs the CPU's ((1 - A) a) c. 1e-5 is ~80 ulps at 1 and 10x the measured worst
// (9.5e-7); a wrong fragment, order or clip is >= 1e-3 off (one 0.2-alpha fragment's colour
// moves a pixel by >= 0.02, swapping two fragments by a1 a2 |c1 - c2|).
constexpr double kCpuColorTolerance = 1e-5;
// Alpha does not depend on shading, only on the interpolated vertex alpha at the hit (the
// interpolation parameter differs by float ulps) and on fp32 accumulation of 1 - prod(1 - a_i):
// 1e-6 is ~8 ulps at 1, 5x the measured worst (2.1e-7).
constexpr double kCpuAlphaTolerance = 1e-6;
// Two CPU fragments of one pixel within this relative depth are a depth tie: the GPU's depths
// differ from the CPU's by up to ~1e-5 relative (rounded_cone_renderer_test.cpp measures 7.8e-6),
// so their order may flip (joint spheres without cap clipping are exact ties: both segments hit
// the same sphere). Colour is not compared there
// when flipping changes it by more than a quarter of the tolerance (a1 a2 |c1 - c2|); alpha is
// order independent and is still compared.
constexpr double kTieRelDepth = 1e-4;
// One RGBA8 level's rounding: packUnorm4x8 stores round(255 x) / 255 (llvmpipe: half to even),
// so every stored channel is within 0.5 / 255 of the float value.
constexpr double kQuantum = 0.5 / 255.0;
// fp32 accumulation slack on top of the analytic quantisation bounds (k-buffer vs peeling).
constexpr double kFloatSlack = 1e-5;

// --- Rendering -------------------------------------------------------------------------------

struct TransparentSettings {
    Transparency mode = Transparency::DepthPeeling;
    int k = 8;
    bool capClipping = true;
    int maxPeelLayers = 0;
    int memoryBudgetMb = 4096;
    std::optional<HaloSpec> halo;  // style.halo
};

struct GpuFrame {
    FrameImages images;
    int peelLayers = 0;
};

Scene transparentScene(const TransparentSettings& s, int width, int height) {
    Scene scene;
    scene.image.width = width;  // the technique checks its memory budget for this size up front
    scene.image.height = height;
    scene.render.transparency = s.mode;
    scene.render.kbufferK = s.k;
    scene.render.capClipping = s.capClipping;
    scene.render.maxPeelLayers = s.maxPeelLayers;
    scene.render.memoryBudgetMb = s.memoryBudgetMb;
    if (s.halo) scene.style.halo = *s.halo;
    // No AOVs: no G-buffer pass (faster; these tests look at RGBA only).
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
    return scene;
}

GpuFrame renderGpu(const StyledLines& lines, const Camera& cam, int w, int h, const TransparentSettings& s) {
    std::unique_ptr<tc::Technique> technique = gl::createTechnique(transparentScene(s, w, h), lines);
    auto* renderer = dynamic_cast<gl::TransparentRenderer*>(technique.get());
    EXPECT_NE(renderer, nullptr) << "createTechnique did not pick the transparent renderer";
    gl::StageTimer timer;
    GpuFrame f;
    technique->render(tc::FrameSetup{0, cam, w, h}, f.images, timer);
    timer.collect();
    if (renderer) f.peelLayers = renderer->lastPeelLayers();
    return f;
}

TransparentSettings peeling(bool capClipping = true) {
    return {Transparency::DepthPeeling, 8, capClipping, 0, 4096, std::nullopt};
}
TransparentSettings kbuffer(int k, bool capClipping = true) {
    return {Transparency::KBuffer, k, capClipping, 0, 4096, std::nullopt};
}
TransparentSettings objectOrder(bool capClipping = true) {
    return {Transparency::ObjectOrder, 8, capClipping, 0, 4096, std::nullopt};
}

// --- CPU side: the reference image and what each pixel's fragment list says -------------------

struct CpuFrame {
    int width = 0, height = 0;
    FrameImages images;                      // renderReferenceTransparent
    std::vector<int> count;                  // fragments per pixel (depth complexity)
    std::vector<std::uint64_t> segmentSet;   // hash of the pixel's sorted segment ids
    std::vector<std::uint64_t> polylineSet;  // hash of the pixel's sorted polyline ids (multiset)
    std::vector<char> colorTie;              // a depth tie whose order changes the colour
    // Analytic bounds of |k-buffer - exact| for this pixel's fragments when each straight channel
    // is rounded to 8 bits (see kbufferBounds).
    std::vector<double> quantColorBound, quantAlphaBound;
    int maxCount = 0;

    std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(width) + std::size_t(x); }

    // Any pixel of the 3x3 neighbourhood with another value of `key`: the pixel lies on a
    // silhouette (of the set of fragments), where one ray more or less through a rim legitimately
    // changes the fragment list between CPU and GPU.
    bool edge(const std::vector<std::uint64_t>& key, int x, int y) const {
        const std::uint64_t k = key[index(x, y)];
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int u = x + dx, v = y + dy;
                if (u >= 0 && v >= 0 && u < width && v < height && key[index(u, v)] != k) return true;
            }
        return false;
    }
    double neighbourhoodMax(const std::vector<double>& values, int x, int y) const {
        double m = 0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int u = x + dx, v = y + dy;
                if (u >= 0 && v >= 0 && u < width && v < height) m = std::max(m, values[index(u, v)]);
            }
        return m;
    }
};

std::uint64_t hashIds(std::vector<std::uint32_t>& ids) {
    std::sort(ids.begin(), ids.end());
    std::uint64_t h = 1469598103934665603ull ^ ids.size();
    for (std::uint32_t id : ids) h = (h ^ (id + 0x9e3779b9u)) * 1099511628211ull;
    return h;
}

// The k-buffer stores each fragment's straight colour c_i and alpha a_i rounded to 8 bits
// (|error| <= q = kQuantum). With T_i = prod_{j<i} (1 - a_j), the composite is
// C = sum T_i a_i c_i and A = 1 - prod (1 - a_i), so to first order
//   |dC| <= q sum_i T_i (a_i + 1)        (dC/dc_i = T_i a_i; |dC/da_i| = T_i |c_i - behind_i| <= T_i)
//   |dA| <= q sum_i prod_{j != i} (1 - a_j) = q sum_i (1 - A) / (1 - a_i).
// Second-order terms are bounded by q^2 n^2 (n fragments), added as they are.
void kbufferBounds(const std::vector<TransparentFragment>& frags, double& colorBound, double& alphaBound) {
    double transmittance = 1, sumColor = 0;
    for (const TransparentFragment& f : frags) {
        sumColor += transmittance * (f.alpha + 1.0);
        transmittance *= 1.0 - f.alpha;
    }
    double sumAlpha = 0;
    for (const TransparentFragment& f : frags) sumAlpha += f.alpha < 1.0f ? transmittance / (1.0 - f.alpha) : 1.0;
    const double n = double(frags.size());
    colorBound = kQuantum * sumColor + kQuantum * kQuantum * n * n;
    alphaBound = kQuantum * sumAlpha + kQuantum * kQuantum * n * n;
}

// `halo`: the reference with halo rings (core/halo.h), drawn over transparentScene's background.
CpuFrame cpuReference(const StyledLines& lines, const Camera& cam, int w, int h, bool capClipping,
                      const std::optional<HaloSpec>& haloSpec = std::nullopt) {
    CpuFrame c;
    c.width = w;
    c.height = h;
    const LightingSpec light;  // the default, as transparentScene's
    std::optional<LineHalo> halo;
    if (haloSpec) halo = lineHalo(*haloSpec, Scene().image.background);
    const LineHalo* ring = halo ? &*halo : nullptr;
    c.images = renderReferenceTransparent(lines, cam, light, w, h, capClipping, &c.count, ring);
    const std::size_t n = std::size_t(w) * h;
    c.segmentSet.assign(n, 0);
    c.polylineSet.assign(n, 0);
    c.colorTie.assign(n, 0);
    c.quantColorBound.assign(n, 0.0);
    c.quantAlphaBound.assign(n, 0.0);
    std::vector<TransparentFragment> frags;
    std::vector<std::uint32_t> ids;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = c.index(x, y);
            collectFragments(lines, pixelRay(cam, w, h, float(x), float(y)), cam, light, capClipping, frags, ring);
            ids.clear();
            // A segment's ring and its tube are different fragments (another colour): where a
            // neighbour pixel has the other, the pixel is on the tube's silhouette.
            for (const auto& f : frags) ids.push_back(2 * f.segment + (f.halo ? 1u : 0u));
            c.segmentSet[i] = hashIds(ids);
            ids.clear();
            for (const auto& f : frags) ids.push_back(lines.polylineId[lines.segmentVertices[2 * f.segment]]);
            c.polylineSet[i] = hashIds(ids);
            for (std::size_t j = 1; j < frags.size(); ++j) {
                const auto &a = frags[j - 1], &b = frags[j];
                if (b.depth - a.depth <= kTieRelDepth * a.depth &&
                    double(a.alpha) * b.alpha * glm::length(a.rgb - b.rgb) > 0.25 * kCpuColorTolerance)
                    c.colorTie[i] = 1;
            }
            kbufferBounds(frags, c.quantColorBound[i], c.quantAlphaBound[i]);
            c.maxCount = std::max(c.maxCount, int(frags.size()));
        }
    return c;
}

// --- Scenes ----------------------------------------------------------------------------------

// Straight alpha per vertex, uniform in [lo, hi], from mt19937's raw output (deterministic).
void setRandomAlpha(StyledLines& lines, std::uint32_t seed, float lo, float hi) {
    std::mt19937 rng(seed);
    for (glm::vec4& c : lines.color) c.w = lo + (hi - lo) * float(rng() >> 8) * (1.0f / 16777216.0f);
}

// Small random transparent scenes: bent polylines, radii varying 3x per vertex, alpha 0.2-0.6.
StyledLines smallTransparentScene(std::uint32_t seed) {
    RandomSceneOptions o;
    o.polylines = 7;
    o.minSegments = 2;
    o.maxSegments = 6;
    o.radiusMin = 0.06f;
    o.radiusRatio = 3.0f;
    o.maxBendDeg = 60.0f;
    StyledLines lines = randomLineScene(seed, o);
    setRandomAlpha(lines, seed * 7919u, 0.2f, 0.6f);
    return lines;
}

// Many overlapping tubes in a small ball: depth complexity well over 16 in the middle.
StyledLines denseScene(std::uint32_t seed, int polylines, float alphaLo, float alphaHi) {
    RandomSceneOptions o;
    o.polylines = polylines;
    o.minSegments = 3;
    o.maxSegments = 6;
    o.radiusMin = 0.04f;
    o.radiusRatio = 2.5f;
    o.stepMin = 0.15f;
    o.stepMax = 0.3f;
    o.maxBendDeg = 50.0f;
    o.extent = 0.3f;
    StyledLines lines = randomLineScene(seed, o);
    setRandomAlpha(lines, seed * 104729u, alphaLo, alphaHi);
    return lines;
}

// --- Comparisons -----------------------------------------------------------------------------

struct CpuGpuComparison {
    std::size_t pixels = 0, covered = 0, compared = 0, edge = 0, ties = 0;
    std::size_t colorOver = 0, alphaOver = 0, coverageOffEdge = 0, edgeMismatch = 0;
    std::size_t markedCompared = 0;  // of the pixels marked by the caller
    double maxColor = 0, maxAlpha = 0;
    std::string problems;
    void note(int x, int y, const std::string& what) {
        if (std::count(problems.begin(), problems.end(), '\n') < 8)
            problems += "  (" + std::to_string(x) + "," + std::to_string(y) + ") " + what + "\n";
    }
    std::string summary() const {
        char s[400];
        std::snprintf(s, sizeof s,
                      "%zu px, covered %zu, compared %zu (colour ties %zu), edge %zu (differing %zu); max colour %.3g, "
                      "max alpha %.3g; over: colour %zu, alpha %zu, coverage off edges %zu",
                      pixels, covered, compared, ties, edge, edgeMismatch, maxColor, maxAlpha, colorOver, alphaOver,
                      coverageOffEdge);
        return s;
    }
};

// GPU image vs CPU reference, pixel by pixel, off the edges of the CPU's `key` (segment or
// polyline set).
CpuGpuComparison compareWithCpu(const FrameImages& gpu, const CpuFrame& cpu, const std::vector<std::uint64_t>& key,
                                const std::vector<char>* marked = nullptr) {
    CpuGpuComparison c;
    c.pixels = cpu.images.pixelCount();
    if (gpu.rgba.size() != cpu.images.rgba.size()) {
        ADD_FAILURE() << "image sizes differ";
        return c;
    }
    for (int y = 0; y < cpu.height; ++y)
        for (int x = 0; x < cpu.width; ++x) {
            const std::size_t i = cpu.index(x, y);
            const float* g = &gpu.rgba[4 * i];
            const float* r = &cpu.images.rgba[4 * i];
            c.covered += cpu.count[i] > 0;
            double dc = 0;
            for (int ch = 0; ch < 3; ++ch) dc = std::max(dc, double(std::abs(g[ch] - r[ch])));
            const double da = std::abs(double(g[3]) - double(r[3]));
            if (cpu.edge(key, x, y)) {
                ++c.edge;
                c.edgeMismatch += dc > kCpuColorTolerance || da > kCpuAlphaTolerance;
                continue;
            }
            if ((g[3] > 0) != (r[3] > 0)) {
                ++c.coverageOffEdge;
                c.note(x, y, "coverage: gpu alpha " + std::to_string(g[3]) + ", cpu " + std::to_string(r[3]));
                continue;
            }
            if (cpu.count[i] == 0) continue;
            ++c.compared;
            if (marked && (*marked)[i]) ++c.markedCompared;
            c.maxAlpha = std::max(c.maxAlpha, da);
            if (!(da <= kCpuAlphaTolerance)) {
                ++c.alphaOver;
                c.note(x, y, "alpha gpu " + std::to_string(g[3]) + " cpu " + std::to_string(r[3]));
            }
            if (cpu.colorTie[i]) {
                ++c.ties;
                continue;
            }
            c.maxColor = std::max(c.maxColor, dc);
            if (!(dc <= kCpuColorTolerance)) {
                ++c.colorOver;
                c.note(x, y,
                       "colour error " + std::to_string(dc) + " (" + std::to_string(cpu.count[i]) + " fragments)");
            }
        }
    return c;
}

void expectMatchesCpu(const FrameImages& gpu, const CpuFrame& cpu, const std::string& label, std::size_t minCompared) {
    const CpuGpuComparison c = compareWithCpu(gpu, cpu, cpu.segmentSet);
    std::printf("[ measured ] %s: %s, max depth complexity %d\n", label.c_str(), c.summary().c_str(), cpu.maxCount);
    EXPECT_GE(c.compared, minCompared) << label << ": too few pixels compared to mean anything";
    EXPECT_GE(c.compared, c.covered / 4) << label << ": too many covered pixels are edges";
    EXPECT_EQ(c.coverageOffEdge, 0u) << label << ": " << c.summary() << "\n" << c.problems;
    // On edges a rim ray may gain or lose a fragment by rounding: rare (measured <= 1 % of the
    // covered pixels), or the edge rule would hide a real difference.
    EXPECT_LE(c.edgeMismatch, c.covered / 50) << label << ": " << c.summary();
    EXPECT_EQ(c.alphaOver, 0u) << label << ": " << c.summary() << "\n" << c.problems;
    EXPECT_EQ(c.colorOver, 0u) << label << ": " << c.summary() << "\n" << c.problems;
    // Colour ties are where tubes interpenetrate (a curve per pair) and, without cap clipping,
    // joint spheres (a fraction of each joint's disc). Most pixels must get the full check.
    EXPECT_LE(c.ties, c.compared / 3) << label << ": " << c.summary();
}

struct PairStats {
    double maxColorOver = 0;  // max over pixels of |a - b| / bound (colour); <= 1 passes
    double maxAlphaOver = 0;
    double maxColor = 0, maxAlpha = 0;
    std::size_t compared = 0, ties = 0;
};

// GPU vs GPU with per-pixel bounds: colour within colourBound(i), alpha within alphaBound(i);
// colour ties (CPU) are skipped for colour only.
PairStats compareGpuPair(const FrameImages& a, const FrameImages& b, const CpuFrame& cpu,
                         const std::function<double(int, int)>& colorBound,
                         const std::function<double(int, int)>& alphaBound, const std::string& label) {
    PairStats s;
    int reported = 0;
    for (int y = 0; y < cpu.height; ++y)
        for (int x = 0; x < cpu.width; ++x) {
            const std::size_t i = cpu.index(x, y);
            const float* pa = &a.rgba[4 * i];
            const float* pb = &b.rgba[4 * i];
            const double da = std::abs(double(pa[3]) - double(pb[3]));
            const double ab = alphaBound(x, y);
            s.maxAlpha = std::max(s.maxAlpha, da);
            s.maxAlphaOver = std::max(s.maxAlphaOver, da / ab);
            if (!(da <= ab) && reported++ < 5)
                ADD_FAILURE() << label << ": alpha at (" << x << "," << y << ") " << pa[3] << " vs " << pb[3]
                              << ", bound " << ab << ", " << cpu.count[i] << " CPU fragments";
            ++s.compared;
            if (cpu.colorTie[i]) {
                ++s.ties;
                continue;
            }
            double dc = 0;
            for (int ch = 0; ch < 3; ++ch) dc = std::max(dc, double(std::abs(pa[ch] - pb[ch])));
            const double cb = colorBound(x, y);
            s.maxColor = std::max(s.maxColor, dc);
            s.maxColorOver = std::max(s.maxColorOver, dc / cb);
            if (!(dc <= cb) && reported++ < 5)
                ADD_FAILURE() << label << ": colour at (" << x << "," << y << ") differs by " << dc << ", bound " << cb
                              << ", " << cpu.count[i] << " CPU fragments";
        }
    return s;
}

double rmse(const FrameImages& a, const FrameImages& b) {
    return compareRgba(a.rgba, b.rgba).rmse;
}

// --- Tests -----------------------------------------------------------------------------------

using TransparencyTest = GlTest;

TEST_F(TransparencyTest, depth_peeling_matches_cpu_reference_on_random_scenes) {
    const int w = 96, h = 72;
    for (std::uint32_t seed : {1u, 2u, 3u}) {
        const StyledLines lines = smallTransparentScene(seed);
        const Camera cam = seed == 3 ? orthographic(eyeFromSeed(seed, 3.0f), {0, 0, 0}, 1.8f)
                                     : lookAt(eyeFromSeed(seed, 2.5f), {0, 0, 0});
        for (bool clip : {true, false}) {
            const std::string label = "seed " + std::to_string(seed) + (clip ? ", cap clipping" : ", no cap clipping");
            SCOPED_TRACE(label);
            const CpuFrame cpu = cpuReference(lines, cam, w, h, clip);
            const GpuFrame gpu = renderGpu(lines, cam, w, h, peeling(clip));
            expectMatchesCpu(gpu.images, cpu, "peel vs cpu, " + label, 500);
            // Peeling stops at the first pass without fragments: the layer count is the depth
            // complexity (+-1 where a rim pixel has a fragment more or less on the GPU).
            EXPECT_NEAR(gpu.peelLayers, cpu.maxCount, 1) << label;
        }
    }
}

// style.halo: the GLSL ring (shaders/transparent_fragment.glsl haloFragment) against its CPU twin
// (core/halo.h), which the ray tracer's halos are tested against too: same fragments, same order,
// same tolerances as the tubes alone.
TEST_F(TransparencyTest, depth_peeling_with_halos_matches_cpu_reference) {
    // Twice the random scenes' resolution: a ring adds two edges (its outer rim and the tube's
    // silhouette) per tube side, and edge pixels are not compared.
    const int w = 192, h = 144;
    HaloSpec halo;
    halo.enabled = true;
    halo.width = 0.8f;
    halo.depth = 3.0f;
    halo.color = glm::vec3(0.9f, 0.6f, 0.1f);
    for (std::uint32_t seed : {1u, 3u}) {
        const StyledLines lines = smallTransparentScene(seed);
        const Camera cam = seed == 3 ? orthographic(eyeFromSeed(seed, 3.0f), {0, 0, 0}, 1.8f)
                                     : lookAt(eyeFromSeed(seed, 2.5f), {0, 0, 0});
        for (bool clip : {true, false}) {
            const std::string label = "halos, seed " + std::to_string(seed) + (clip ? ", cap clipping" : "");
            SCOPED_TRACE(label);
            const CpuFrame cpu = cpuReference(lines, cam, w, h, clip, halo);
            const CpuFrame plain = cpuReference(lines, cam, w, h, clip);
            TransparentSettings settings = peeling(clip);
            settings.halo = halo;
            expectMatchesCpu(renderGpu(lines, cam, w, h, settings).images, cpu, "peel vs cpu, " + label, 500);
            // Not vacuous: the rings add fragments to many pixels.
            std::size_t ringPixels = 0;
            for (std::size_t i = 0; i < cpu.count.size(); ++i) ringPixels += cpu.count[i] > plain.count[i];
            EXPECT_GT(ringPixels, 2000u) << label;
        }
    }
}

TEST_F(TransparencyTest, kbuffer_matches_depth_peeling_when_k_exceeds_depth_complexity) {
    const int w = 96, h = 72;
    int tested = 0;
    for (std::uint32_t seed : {1u, 2u, 4u}) {
        const StyledLines lines = smallTransparentScene(seed);
        const Camera cam = lookAt(eyeFromSeed(seed, 3.0f), {0, 0, 0});
        for (bool clip : {true, false}) {
            const CpuFrame cpu = cpuReference(lines, cam, w, h, clip);
            // GPU rims can add one fragment to the CPU's count.
            const int k = cpu.maxCount + 1;
            if (k > 16) continue;
            ++tested;
            const std::string label = "seed " + std::to_string(seed) + ", k " + std::to_string(k) +
                                      (clip ? ", cap clipping" : ", no cap clipping");
            const GpuFrame peel = renderGpu(lines, cam, w, h, peeling(clip));
            const GpuFrame kb = renderGpu(lines, cam, w, h, kbuffer(k, clip));
            ASSERT_LE(peel.peelLayers, k) << label;
            // Bounds: kbufferBounds of the pixel's CPU fragments (neighbourhood max, for rims
            // where the GPU list differs by one fragment) + fp32 slack.
            const PairStats s = compareGpuPair(
                kb.images, peel.images, cpu,
                [&](int x, int y) { return cpu.neighbourhoodMax(cpu.quantColorBound, x, y) + kFloatSlack; },
                [&](int x, int y) { return cpu.neighbourhoodMax(cpu.quantAlphaBound, x, y) + kFloatSlack; }, label);
            std::printf(
                "[ measured ] kbuffer vs peel, %s: max colour %.3g (%.2f of bound), max alpha %.3g (%.2f of "
                "bound), colour ties %zu\n",
                label.c_str(), s.maxColor, s.maxColorOver, s.maxAlpha, s.maxAlphaOver, s.ties);
        }
    }
    EXPECT_GE(tested, 4) << "the scenes are too deep for k <= 16";
}

// Measured on the dense scenes: the error of each k against depth peeling, object order last.
struct DenseErrors {
    int maxDepthComplexity = 0, peelLayers = 0;
    double objectOrder = 0;
    std::vector<double> kbuffer;  // for kDenseKs
    FrameImages peel;
    CpuFrame cpu;
};

constexpr int kDenseKs[] = {1, 2, 4, 8, 16};

DenseErrors denseErrors(const StyledLines& lines, const Camera& cam, int w, int h, bool clip,
                        const std::string& label) {
    DenseErrors e;
    e.cpu = cpuReference(lines, cam, w, h, clip);
    e.maxDepthComplexity = e.cpu.maxCount;
    GpuFrame peel = renderGpu(lines, cam, w, h, peeling(clip));
    e.peelLayers = peel.peelLayers;
    e.peel = std::move(peel.images);
    const FrameImages oo = renderGpu(lines, cam, w, h, objectOrder(clip)).images;
    e.objectOrder = rmse(oo, e.peel);
    std::printf("[ measured ] %s: max depth complexity %d, peeled %d layers; RMSE vs peel: object order %.5f",
                label.c_str(), e.maxDepthComplexity, e.peelLayers, e.objectOrder);
    for (int k : kDenseKs) {
        const FrameImages kb = renderGpu(lines, cam, w, h, kbuffer(k, clip)).images;
        e.kbuffer.push_back(rmse(kb, e.peel));
        std::printf(", k=%d %.5f", k, e.kbuffer.back());
        // Alpha is order independent (the k-buffer only quantises it): see
        // alpha_is_order_independent_across_techniques for the bound.
        const PairStats s = compareGpuPair(
            kb, e.peel, e.cpu, [](int, int) { return 1e30; },
            [&](int x, int y) { return e.cpu.neighbourhoodMax(e.cpu.quantAlphaBound, x, y) + kFloatSlack; },
            label + ", k=" + std::to_string(k) + " alpha");
        (void)s;
    }
    std::printf("\n");
    return e;
}

// Monotonic up to this absolute RMSE: once k reaches the depth complexity of most pixels the
// remaining error is the RGBA8 rounding of each fragment (the floor: measured 5e-4 RMSE at alpha
// 0.2-0.5, 2e-3 at alpha 0.05), and k and 2k blend the same rounded values in slightly different
// orders, so neighbouring k may differ by a small fraction of that floor (measured: 2e-5). 1e-4
// is 1/5 of the lower floor; the steps while k is below the depth complexity of most pixels are
// >= 6.8e-4 (measured).
constexpr double kMonotonicSlack = 1e-4;

void expectErrorDecreasesWithK(const DenseErrors& e, const std::string& label) {
    for (std::size_t i = 1; i < e.kbuffer.size(); ++i)
        EXPECT_LE(e.kbuffer[i], e.kbuffer[i - 1] + kMonotonicSlack)
            << label << ": k=" << kDenseKs[i] << " is worse than k=" << kDenseKs[i - 1];
}

TEST_F(TransparencyTest, kbuffer_error_decreases_with_k_and_object_order_is_worst_on_dense_scene) {
    const int w = 80, h = 60;
    const StyledLines lines = denseScene(31, 70, 0.2f, 0.5f);
    const Camera cam = lookAt(eyeFromSeed(31, 2.6f), {0, 0, 0});
    for (bool clip : {true, false}) {
        const std::string label = std::string("dense, alpha 0.2-0.5, ") + (clip ? "cap clipping" : "no cap clipping");
        SCOPED_TRACE(label);
        const DenseErrors e = denseErrors(lines, cam, w, h, clip, label);
        EXPECT_GT(e.maxDepthComplexity, 16) << "not dense enough to exceed the largest k";
        EXPECT_NEAR(e.peelLayers, e.maxDepthComplexity, 1);
        expectErrorDecreasesWithK(e, label);
        // Not vacuous: the order matters in this scene (k = 1 at least twice the floor of k = 16).
        EXPECT_GT(e.kbuffer.front(), 2.0 * e.kbuffer.back()) << label << ": k barely matters in this scene";
        // Object order blends whole segments in sorted order; the k-buffer with k = 1 already
        // reorders each pixel's nearest pair, so object order must be at least as bad.
        EXPECT_GE(e.objectOrder, e.kbuffer.front()) << label << ": object order beats k=1";
    }
}

TEST_F(TransparencyTest, kbuffer_error_decreases_with_k_at_opacity_0_05_with_over_50_layers) {
    const int w = 64, h = 48;
    const StyledLines lines = denseScene(41, 220, 0.05f, 0.05f);
    const Camera cam = lookAt(eyeFromSeed(41, 2.2f), {0, 0, 0});
    const std::string label = "dense, alpha 0.05, cap clipping";
    const DenseErrors e = denseErrors(lines, cam, w, h, true, label);
    EXPECT_GE(e.maxDepthComplexity, 50);
    EXPECT_GE(e.peelLayers, 50);
    EXPECT_NEAR(e.peelLayers, e.maxDepthComplexity, 1);
    expectErrorDecreasesWithK(e, label);
    // At alpha 0.05 swapping two fragments changes a pixel by only a1 a2 |c1 - c2| <= 0.0025, while
    // every k-buffer entry stores alpha 0.05 as 13/255 = 0.0510 (+2 %, the same way for every
    // fragment: a bias, not noise). So here the k-buffer's error vs depth peeling is its RGBA8
    // floor for every k, and object order (float, no rounding) is closer to depth peeling than
    // any k (measured: object order 1.2e-3, k-buffer 2.6e-3 for every k). Checked: the k-buffer
    // stays at that floor (k = 1 within 1.5x of k = 16), and object order's error is not zero.
    EXPECT_LE(e.kbuffer.front(), 1.5 * e.kbuffer.back()) << label;
    EXPECT_GT(e.objectOrder, 0.0) << label << ": object order equals depth peeling: the order never matters here";
}

TEST_F(TransparencyTest, alpha_is_order_independent_across_techniques) {
    // Alpha = 1 - prod(1 - a_i) whatever the order. Object order and depth peeling blend the same
    // float alphas (differences: fp32 accumulation, kFloatSlack); the k-buffer blends alphas
    // rounded to 8 bits, within kbufferBounds' alpha bound (first order in q = 0.5 / 255, per
    // pixel from its fragments) + kFloatSlack.
    const int w = 96, h = 72;
    struct Case {
        StyledLines lines;
        Camera cam;
        bool clip;
        std::string label;
    };
    std::vector<Case> cases;
    for (std::uint32_t seed : {1u, 2u})
        for (bool clip : {true, false})
            cases.push_back({smallTransparentScene(seed), lookAt(eyeFromSeed(seed, 3.0f), {0, 0, 0}), clip,
                             "seed " + std::to_string(seed) + (clip ? ", cap clipping" : ", no cap clipping")});
    cases.push_back({denseScene(31, 70, 0.2f, 0.5f), lookAt(eyeFromSeed(31, 2.6f), {0, 0, 0}), true, "dense"});
    for (const Case& c : cases) {
        SCOPED_TRACE(c.label);
        const CpuFrame cpu = cpuReference(c.lines, c.cam, w, h, c.clip);
        const FrameImages peel = renderGpu(c.lines, c.cam, w, h, peeling(c.clip)).images;
        const auto noColor = [](int, int) { return 1e30; };
        const PairStats oo = compareGpuPair(
            renderGpu(c.lines, c.cam, w, h, objectOrder(c.clip)).images, peel, cpu, noColor,
            [](int, int) { return kFloatSlack; }, c.label + ", object order");
        std::printf("[ measured ] alpha, %s (max depth complexity %d): object order vs peel %.3g", c.label.c_str(),
                    cpu.maxCount, oo.maxAlpha);
        for (int k : {1, 3, 16}) {
            const PairStats kb = compareGpuPair(
                renderGpu(c.lines, c.cam, w, h, kbuffer(k, c.clip)).images, peel, cpu, noColor,
                [&](int x, int y) { return cpu.neighbourhoodMax(cpu.quantAlphaBound, x, y) + kFloatSlack; },
                c.label + ", k=" + std::to_string(k));
            std::printf(", k=%d %.3g (%.2f of bound)", k, kb.maxAlpha, kb.maxAlphaOver);
        }
        std::printf("\n");
    }
}

TEST_F(TransparencyTest, depth_peeling_stops_after_max_layers_and_its_alpha_is_at_most_the_full_peel) {
    const int w = 96, h = 72;
    // Without cap clipping: joint spheres add layers (6 here).
    const StyledLines lines = smallTransparentScene(3);
    const Camera cam = lookAt(eyeFromSeed(3, 2.5f), {0, 0, 0});
    const CpuFrame cpu = cpuReference(lines, cam, w, h, false);
    const GpuFrame full = renderGpu(lines, cam, w, h, peeling(false));
    ASSERT_GT(full.peelLayers, 3) << "the scene must be deeper than the limits tested";
    for (int limit : {1, 3}) {
        TransparentSettings s = peeling(false);
        s.maxPeelLayers = limit;
        const GpuFrame part = renderGpu(lines, cam, w, h, s);
        EXPECT_EQ(part.peelLayers, limit);
        std::size_t lower = 0, identical = 0, shallow = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = cpu.index(x, y);
                // The first `limit` layers are blended by the same operations in the same order, and
                // every further layer adds (1 - A) a >= 0: exact, no tolerance.
                ASSERT_LE(part.images.rgba[4 * i + 3], full.images.rgba[4 * i + 3]) << "(" << x << "," << y << ")";
                lower += part.images.rgba[4 * i + 3] < full.images.rgba[4 * i + 3];
                // Pixels with at most `limit` fragments (also around them: rims) are complete.
                int deepest = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int u = std::clamp(x + dx, 0, w - 1), v = std::clamp(y + dy, 0, h - 1);
                        deepest = std::max(deepest, cpu.count[cpu.index(u, v)]);
                    }
                if (deepest <= limit) {
                    ++shallow;
                    bool same = true;
                    for (int ch = 0; ch < 4; ++ch) same &= part.images.rgba[4 * i + ch] == full.images.rgba[4 * i + ch];
                    identical += same;
                }
            }
        std::printf("[ measured ] max_layers %d of %d: %zu px with lower alpha, %zu/%zu shallow px identical\n", limit,
                    full.peelLayers, lower, identical, shallow);
        EXPECT_GE(lower, 20u) << "the limit changed (almost) nothing";
        EXPECT_EQ(identical, shallow);
    }
}

TEST_F(TransparencyTest, kbuffer_over_memory_budget_is_an_input_error_naming_the_key) {
    const StyledLines lines = smallTransparentScene(1);
    const Camera cam = lookAt(eyeFromSeed(1, 3.0f), {0, 0, 0});
    TransparentSettings s = kbuffer(16);
    s.memoryBudgetMb = 1;
    // 128 x 96 x (16 B colour target + 16 x 8 B entries) = 1.69 MiB > 1 MiB.
    try {
        renderGpu(lines, cam, 128, 96, s);
        ADD_FAILURE() << "no error over the memory budget";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("render.memory_budget_mb: ", 0), 0u) << msg;
        EXPECT_NE(msg.find("k=16"), std::string::npos) << msg;
        EXPECT_NE(msg.find("128x96"), std::string::npos) << msg;
        EXPECT_NE(msg.find("budget of 1 MB"), std::string::npos) << msg;
    }
    // 64 x 48 x 144 B = 0.42 MiB fits.
    EXPECT_NO_THROW(renderGpu(lines, cam, 64, 48, s));
}

TEST_F(TransparencyTest, transparent_modes_write_first_surface_aovs_only_when_requested) {
    // With output.aov* set, depth / normal / id come from the same G-buffer pass as the opaque
    // technique's (the first surface of the union of tubes, whatever its alpha): bit-identical.
    // Without, the transparent path skips that pass and leaves them background.
    const int w = 64, h = 48;
    const StyledLines lines = smallTransparentScene(2);
    const Camera cam = lookAt(eyeFromSeed(2, 2.5f), {0, 0, 0});
    Scene opaque;
    opaque.output.aovDepth = opaque.output.aovNormal = opaque.output.aovId = true;
    gl::StageTimer timer;
    FrameImages reference;
    gl::createTechnique(opaque, lines)->render(tc::FrameSetup{0, cam, w, h}, reference, timer);
    timer.collect();
    std::size_t hits = 0;
    for (std::uint32_t id : reference.id) hits += id != kBackgroundId;
    ASSERT_GT(hits, 300u);
    for (Transparency mode : {Transparency::ObjectOrder, Transparency::KBuffer, Transparency::DepthPeeling}) {
        TransparentSettings s;
        s.mode = mode;
        Scene scene = transparentScene(s, w, h);
        scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = true;
        FrameImages with;
        gl::createTechnique(scene, lines)->render(tc::FrameSetup{0, cam, w, h}, with, timer);
        timer.collect();
        EXPECT_EQ(with.depth, reference.depth) << int(mode);
        EXPECT_EQ(with.normal, reference.normal) << int(mode);
        EXPECT_EQ(with.id, reference.id) << int(mode);
        const FrameImages without = renderGpu(lines, cam, w, h, s).images;
        EXPECT_EQ(without.rgba, with.rgba) << int(mode) << ": the G-buffer pass changed the colour";
        EXPECT_TRUE(std::all_of(without.depth.begin(), without.depth.end(), [](float d) { return std::isinf(d); }));
        EXPECT_TRUE(
            std::all_of(without.id.begin(), without.id.end(), [](std::uint32_t id) { return id == kBackgroundId; }));
    }
}

TEST_F(TransparencyTest, coincident_fragments_of_duplicated_tubes_are_all_blended) {
    // Two identical polylines (duplicated data): every ray gets two fragments with bit-identical
    // depths. Depth peeling orders them by (depth, segment id), the k-buffer keeps equal keys, so
    // no fragment is lost or doubled: alpha 1 - (1 - a)^2 wherever the tube is seen once.
    const float a = 0.3f;
    const TestPolyline line = {{{-0.8f, -0.2f, 0.1f}, 0.2f, {0.8f, 0.3f, 0.2f, a}},
                               {{0.1f, 0.25f, -0.1f}, 0.15f, {0.2f, 0.7f, 0.3f, a}},
                               {{0.8f, -0.1f, 0.2f}, 0.22f, {0.3f, 0.3f, 0.9f, a}}};
    const StyledLines lines = makeStyledLines({line, line});
    const Camera cam = lookAt({0.3f, 0.4f, 3.0f}, {0, 0, 0});
    const int w = 96, h = 72;
    for (bool clip : {true, false}) {
        const CpuFrame cpu = cpuReference(lines, cam, w, h, clip);
        for (const TransparentSettings& s : {peeling(clip), kbuffer(4, clip), objectOrder(clip)}) {
            const std::string label = std::string(s.mode == Transparency::DepthPeeling ? "depth peeling"
                                                  : s.mode == Transparency::KBuffer    ? "k-buffer"
                                                                                       : "object order") +
                                      (clip ? ", cap clipping" : ", no cap clipping");
            const GpuFrame frame = renderGpu(lines, cam, w, h, s);
            const FrameImages& gpu = frame.images;
            // One peel per fragment, even with equal depths (the segment id in the peel key).
            if (s.mode == Transparency::DepthPeeling) {
                EXPECT_EQ(frame.peelLayers, cpu.maxCount) << label;
            }
            // The k-buffer stores 0.3 as 77/255 (0.30196): alpha within 2 q of the float value.
            const double tolerance = s.mode == Transparency::KBuffer ? 2 * kQuantum + kFloatSlack : kCpuAlphaTolerance;
            std::size_t twoLayers = 0, wrong = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const std::size_t i = cpu.index(x, y);
                    if (cpu.count[i] != 2 || cpu.edge(cpu.segmentSet, x, y)) continue;
                    ++twoLayers;
                    wrong += std::abs(gpu.rgba[4 * i + 3] - (1.0 - (1.0 - a) * (1.0 - a))) > tolerance;
                }
            std::printf("[ measured ] duplicated tubes, %s: %zu px with two coincident fragments, %zu wrong\n",
                        label.c_str(), twoLayers, wrong);
            EXPECT_GT(twoLayers, 500u) << label;
            EXPECT_EQ(wrong, 0u) << label;
        }
    }
}

// --- Cap clipping ------------------------------------------------------------------------------

constexpr float kTubeAlpha = 0.4f;
const glm::vec3 kTubeColor(0.7f, 0.45f, 0.2f);

// A straight polyline along x from -1 to 1, radius r, cut at `cuts` uneven interior points (none
// when 0): the same tube either way, if cap clipping works.
StyledLines straightTube(int cuts, float r) {
    TestPolyline line;
    const glm::vec4 color(kTubeColor, kTubeAlpha);
    line.push_back({{-1.0f, 0, 0}, r, color});
    for (int i = 1; i <= cuts; ++i) {
        const float x = -1.0f + 2.0f * (float(i) + 0.3f * std::sin(1.7f * float(i))) / float(cuts + 1);
        line.push_back({{x, 0, 0}, r, color});
    }
    line.push_back({{1.0f, 0, 0}, r, color});
    return makeStyledLines({line});
}

// World x where the pixel column's ray at the middle row meets the plane z = 0 (the tube's axis plane).
float columnX(const Camera& cam, int w, int h, int x) {
    const Ray ray = pixelRay(cam, w, h, float(x), float(h / 2));
    return ray.origin.x + ray.dir.x * (-ray.origin.z / ray.dir.z);
}

TEST_F(TransparencyTest, cap_clipped_straight_polyline_has_the_alpha_of_one_long_segment) {
    const float r = 0.15f;
    const StyledLines single = straightTube(0, r), cut = straightTube(12, r);
    ASSERT_EQ(cut.segmentCount(), 13u);
    const int w = 160, h = 56;
    for (const Camera& cam :
         {orthographic({0, 0, 3}, {0, 0, 0}, 0.8f), lookAt({0.15f, 0.6f, 2.2f}, {0, 0, 0}, {0, 1, 0}, 30.0f)}) {
        const std::string view =
            cam.projection == Projection::Orthographic ? "orthographic side view" : "perspective, oblique";
        SCOPED_TRACE(view);
        const FrameImages one = renderGpu(single, cam, w, h, peeling(true)).images;
        const FrameImages clipped = renderGpu(cut, cam, w, h, peeling(true)).images;
        const FrameImages unclipped = renderGpu(cut, cam, w, h, peeling(false)).images;
        std::size_t compared = 0, rims = 0, mismatched = 0, notA = 0, beads = 0;
        double maxDiff = 0, maxBead = 0;
        auto alpha = [&](const FrameImages& f, int x, int y) { return f.rgba[4 * (std::size_t(y) * w + x) + 3]; };
        for (int x = 0; x < w; ++x) {
            // The caps: beyond the end vertices, where the profile changes anyway.
            if (std::abs(columnX(cam, w, h, x)) > 1.0f - 1.5f * r) continue;
            for (int y = 0; y < h; ++y) {
                // Rows at the tube's silhouette (the single segment's coverage changes in the 3x3
                // neighbourhood): a grazing ray may hit one cylinder and miss the other by rounding.
                bool rim = false;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int u = std::clamp(x + dx, 0, w - 1), v = std::clamp(y + dy, 0, h - 1);
                        rim |= (alpha(one, u, v) > 0) != (alpha(one, x, y) > 0);
                    }
                if (rim) {
                    ++rims;
                    continue;
                }
                const float a1 = alpha(one, x, y), ac = alpha(clipped, x, y), au = alpha(unclipped, x, y);
                if (a1 == 0) continue;
                ++compared;
                // One fragment of alpha 0.4 on both sides; 1e-6 covers the float interpolation of the
                // (equal) vertex alphas. A bead (2 fragments) is 0.64: 0.24 off.
                const double d = std::abs(double(ac) - double(a1));
                maxDiff = std::max(maxDiff, d);
                mismatched += d > 1e-6;
                notA += std::abs(double(ac) - kTubeAlpha) > 1e-6;
                const double bead = double(au) - double(a1);
                maxBead = std::max(maxBead, bead);
                beads += bead > 0.1;
            }
        }
        std::printf(
            "[ measured ] straight tube, %s: %zu px compared (%zu rim px skipped): clipped vs single max |dA| "
            "%.3g; unclipped: %zu bead px, max +%.3f\n",
            view.c_str(), compared, rims, maxDiff, beads, maxBead);
        EXPECT_GT(compared, 500u);
        EXPECT_EQ(mismatched, 0u) << "cap-clipped joints differ from one long segment";
        EXPECT_EQ(notA, 0u) << "the cap-clipped tube is not a single layer of alpha " << kTubeAlpha;
        // Without cap clipping every joint sphere is at least a second layer: 1 - 0.6^2 = 0.64 vs
        // 0.4 (joints closer than a radius stack more: up to 4 layers here, +0.47).
        EXPECT_GT(beads, 12u * 10u) << "without cap clipping the joints should show";
        EXPECT_GE(maxBead, 0.24 - 1e-3);
    }
}

// A polyline with bends of 30-60 degrees at every joint (random axis), segment lengths 0.35-0.5
// and per-vertex radii from `rLo` to `rHi` (equal: constant radius).
TestPolyline bentPolyline(std::uint32_t seed, glm::vec3 start, int segments, float rLo, float rHi) {
    std::mt19937 rng(seed);
    auto uniform = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) * (1.0f / 16777216.0f); };
    TestPolyline line;
    glm::vec3 x = start;
    glm::vec3 dir = glm::normalize(glm::vec3(1.0f, uniform(-0.3f, 0.3f), uniform(-0.3f, 0.3f)));
    for (int v = 0; v <= segments; ++v) {
        line.push_back({x, uniform(rLo, rHi), glm::vec4(kTubeColor, kTubeAlpha)});
        // Rotate dir by 30-60 degrees about a random axis perpendicular to it, keeping the line
        // roughly facing the camera (+z): the axis is mostly z.
        glm::vec3 axis = glm::normalize(glm::cross(dir, glm::vec3(uniform(-0.4f, 0.4f), uniform(-0.4f, 0.4f), 1.0f)));
        const float bend = glm::radians(uniform(30.0f, 60.0f)) * (rng() & 1 ? 1.0f : -1.0f);
        const glm::vec3 perp = glm::normalize(glm::cross(axis, dir));
        const float step = uniform(0.35f, 0.5f);
        x += step * dir;
        dir = glm::normalize(std::cos(bend) * dir + std::sin(bend) * perp);
    }
    return line;
}

// Pixels whose ray passes within the joint sphere of an interior vertex.
std::vector<char> jointPixels(const StyledLines& lines, const Camera& cam, int w, int h) {
    std::vector<char> joint(std::size_t(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Ray ray = pixelRay(cam, w, h, float(x), float(y));
            for (std::size_t v = 0; v < lines.vertexCount(); ++v) {
                if (lines.flags[v] & (FirstOfPolyline | LastOfPolyline)) continue;
                const glm::vec3 p(lines.positionRadius[v]);
                const glm::vec3 q = ray.origin + glm::dot(p - ray.origin, ray.dir) * ray.dir;
                if (glm::distance(p, q) < lines.positionRadius[v].w) joint[std::size_t(y) * w + x] = 1;
            }
        }
    return joint;
}

TEST_F(TransparencyTest, cap_clipped_bent_polylines_match_cpu_reference_and_show_no_joint_beads) {
    const int w = 128, h = 96;
    const Camera cam = lookAt({0.2f, 0.3f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 40.0f);
    for (bool varyingRadius : {false, true}) {
        const float rLo = varyingRadius ? 0.05f : 0.09f, rHi = varyingRadius ? 0.13f : 0.09f;
        const StyledLines lines = makeStyledLines({bentPolyline(5, {-1.3f, 0.6f, 0.0f}, 6, rLo, rHi),
                                                   bentPolyline(6, {-1.3f, -0.2f, -0.3f}, 6, rLo, rHi),
                                                   bentPolyline(7, {-1.2f, -0.9f, 0.2f}, 6, rLo, rHi)});
        const std::string label = varyingRadius ? "radii 0.05-0.13" : "constant radius 0.09";
        SCOPED_TRACE(label);
        const std::vector<char> joint = jointPixels(lines, cam, w, h);
        const CpuFrame cpuOn = cpuReference(lines, cam, w, h, true);
        const CpuFrame cpuOff = cpuReference(lines, cam, w, h, false);
        const FrameImages gpuOn = renderGpu(lines, cam, w, h, peeling(true)).images;
        const FrameImages gpuOff = renderGpu(lines, cam, w, h, peeling(false)).images;
        // Against the CPU reference, off the edges of each pixel's polyline multiset: with cap
        // clipping a joint changes which segment owns the entry, not how many entries a polyline
        // has, so joints are compared; silhouettes and the thin crescents of bends with radius
        // changes (core/cap_clipping.h) are edges. Same tolerances as the random scenes.
        const CpuGpuComparison on = compareWithCpu(gpuOn, cpuOn, cpuOn.polylineSet, &joint);
        const CpuGpuComparison off = compareWithCpu(gpuOff, cpuOff, cpuOff.polylineSet, &joint);
        std::size_t jointTotal = 0, jointSingle = 0, jointNotA = 0, beadsCpu = 0, beadsGpu = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = cpuOn.index(x, y);
                if (!joint[i]) continue;
                ++jointTotal;
                beadsCpu += cpuOff.images.rgba[4 * i + 3] > cpuOn.images.rgba[4 * i + 3] + 0.1f;
                beadsGpu += gpuOff.rgba[4 * i + 3] > gpuOn.rgba[4 * i + 3] + 0.1f;
                // One polyline entered once (not on an edge): exactly one layer of alpha 0.4.
                if (cpuOn.count[i] == 1 && !cpuOn.edge(cpuOn.polylineSet, x, y)) {
                    ++jointSingle;
                    jointNotA += std::abs(gpuOn.rgba[4 * i + 3] - kTubeAlpha) > 1e-6f;
                }
            }
        std::printf(
            "[ measured ] bent polylines, %s: cap clipping: %s, joint px compared %zu of %zu; no cap "
            "clipping: %s; joint px single layer %zu (not alpha 0.4: %zu); bead px cpu %zu gpu %zu\n",
            label.c_str(), on.summary().c_str(), on.markedCompared, jointTotal, off.summary().c_str(), jointSingle,
            jointNotA, beadsCpu, beadsGpu);
        for (const CpuGpuComparison* c : {&on, &off}) {
            EXPECT_EQ(c->coverageOffEdge, 0u) << c->summary() << "\n" << c->problems;
            EXPECT_EQ(c->alphaOver, 0u) << c->summary() << "\n" << c->problems;
            EXPECT_EQ(c->colorOver, 0u) << c->summary() << "\n" << c->problems;
        }
        // Not vacuous: most joint pixels are compared, not skipped as edges.
        EXPECT_GE(on.markedCompared, jointTotal / 2) << on.summary();
        EXPECT_EQ(jointNotA, 0u);
        EXPECT_GE(jointSingle, jointTotal / 2);
        // And the joints do show without cap clipping, on both sides.
        EXPECT_GE(beadsCpu, jointTotal / 4);
        EXPECT_GE(beadsGpu, jointTotal / 4);
    }
}

}  // namespace
}  // namespace tc::test
