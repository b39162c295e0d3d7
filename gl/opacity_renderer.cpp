#include "gl/opacity_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <ctime>
#include <iostream>
#include <limits>

#include "core/error.h"
#include "core/fragment_occlusion.h"
#include "core/occlusion_matrix.h"
#include "core/stage_sink.h"
#include "core/tiling.h"
#include "gl/bindings.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/shader_library.h"

namespace tc::gl {

namespace {

// Depth, part, fraction, colour and the next link, each a 4-byte array (shaders/opacity_common.glsl).
constexpr std::size_t kNodeBytes = 5 * 4;
constexpr std::uint32_t kEndOfList = 0xFFFFFFFFu;

struct PartW {
    float localW;
    std::uint32_t firstPart;
};

// Polyline offsets of styled lines: styling keeps the vertex order, and each polyline starts with
// a FirstOfPolyline vertex.
std::vector<std::uint32_t> polylineOffsets(const StyledLines& lines) {
    std::vector<std::uint32_t> offsets;
    for (std::size_t v = 0; v < lines.vertexCount(); ++v)
        if (lines.flags[v] & FirstOfPolyline) offsets.push_back(std::uint32_t(v));
    offsets.push_back(std::uint32_t(lines.vertexCount()));
    if (offsets.size() == 1) offsets.insert(offsets.begin(), 0u);
    return offsets;
}

// Process CPU time (all threads) since c0: on a shared machine a stage's wall time includes
// waiting for the cores; its CPU time does not.
double cpuMsSince(std::clock_t c0) {
    return 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC;
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::unique_ptr<OpacityRenderer> OpacityRenderer::create(const Scene& scene, const StyledLines& lines,
                                                         const std::vector<float>* vertexAttribute, SystemSink sink) {
    std::unique_ptr<OpacityRenderer> r(
        new OpacityRenderer(LineGeometry::create(lines, scene.render.billboards, {}, scene.render.billboardShape)));
    const RenderSpec& rs = scene.render;
    r->m_spec = rs.opacity;
    r->m_capClipping = rs.capClipping;
    r->m_geometry.setCapClipping(rs.capClipping);
    if (scene.style.halo.enabled) r->m_geometry.enableHalo(lineHalo(scene.style.halo, scene.image.background));
    r->m_memoryBudgetBytes = std::size_t(rs.memoryBudgetMb) * 1024 * 1024;
    r->m_samples = scene.image.samples;
    r->m_lighting = scene.lighting;
    r->m_sink = std::move(sink);
    if (r->m_spec.pipeline && r->m_sink)
        throw InputError(scene.file +
                         ": render.opacity.pipeline: a pipelined solve belongs to no one frame, so the "
                         "system cannot be dumped (--dump-system, render.opacity.dump_dir)");
    if (rs.ao.enabled)
        throw InputError(scene.file + ": render.ao: not available with render.transparency \"opacity_optimization\"");
    if (scene.output.aovDepth || scene.output.aovNormal || scene.output.aovId)
        r->m_gbuffer = GBufferPass::create(r->m_geometry);

    // Parts and importance (core/opacity_optimization.h).
    std::vector<glm::vec3> positions(lines.vertexCount());
    for (std::size_t v = 0; v < positions.size(); ++v) positions[v] = glm::vec3(lines.positionRadius[v]);
    const std::vector<std::uint32_t> offsets = polylineOffsets(lines);
    r->m_parts = partitionLines(positions, offsets, r->m_spec.segmentsPerLine);
    if (r->m_spec.importance == OpacityOptimizationSpec::Importance::Attribute) {
        if (!vertexAttribute)
            throw InputError(scene.file + ": render.opacity.importance.attribute: \"" + r->m_spec.attribute +
                             "\" needs the dataset's attributes (render through `tubecast render`)");
        TC_CHECK_OP(vertexAttribute->size(), ==, lines.vertexCount());
    }
    r->m_importance = partImportance(r->m_parts, positions, offsets, r->m_spec, vertexAttribute);

    std::vector<PartW> partW(lines.vertexCount());
    for (std::size_t v = 0; v < partW.size(); ++v)
        partW[v] = {r->m_parts.vertexLocalW[v], r->m_parts.vertexFirstPart[v]};
    r->m_vertexPartW = makeBuffer(std::max<std::size_t>(1, partW.size()) * sizeof(PartW), partW.data());
    r->m_counter = makeBuffer(sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);

    r->m_buildProgram = r->m_geometry.compileDrawProgram("opacity_build.frag");
    r->resize(scene.image.width, scene.image.height);
    return r;
}

PixelBuffers OpacityRenderer::pixelBuffers(const Scene& scene) {
    const OutputSpec& o = scene.output;
    const std::size_t aovs = o.aovDepth || o.aovNormal || o.aovId ? GBufferPass::kBytesPerPixel : 0;
    return {16 + 4 + aovs, 4, "opacity_optimization"};  // resize(): RGBA32F target, list heads
}

void OpacityRenderer::resize(int width, int height) {
    if (width == m_width && height == m_height) return;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const std::size_t fixed = pixels * (16 + 4);  // RGBA32F target + list heads
    if (fixed + 64 * kNodeBytes > m_memoryBudgetBytes)
        throw InputError("render.memory_budget_mb: opacity optimization at " + std::to_string(width) + "x" +
                         std::to_string(height) + " needs " + std::to_string(fixed / (1024 * 1024) + 1) +
                         " MB for the target and list heads alone, over the budget of " +
                         std::to_string(m_memoryBudgetBytes / (1024 * 1024)) + " MB");
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    std::size_t capacity = (m_memoryBudgetBytes - fixed) / kNodeBytes;
    if (maxBlock > 0) capacity = std::min(capacity, std::size_t(maxBlock) / 4);
    capacity = std::min<std::size_t>(capacity, 0xFFFFFFF0u);  // node indices are 32-bit
    m_capacity = capacity;
    m_width = width;
    m_height = height;
    m_color = makeTexture2D(GL_RGBA32F, width, height);
    m_framebuffer = makeFramebuffer({&m_color}, nullptr, "opacity optimization target");
    m_heads = makeBuffer(pixels * sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);  // sorted links come back
    const GLuint end = kEndOfList;
    glClearNamedBufferData(m_heads.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &end);
    m_nodeDepth = makeBuffer(capacity * 4);
    m_nodePart = makeBuffer(capacity * 4);
    m_nodeFrac = makeBuffer(capacity * 4);
    m_nodeColor = makeBuffer(capacity * 4);
    m_next = makeBuffer(capacity * sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

FragmentLists OpacityRenderer::readAndSortLists(int width, int height, std::uint64_t stored,
                                                std::vector<std::uint32_t>& colors) {
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    std::vector<std::uint32_t> heads(pixels), next(stored), part(stored), color(stored);
    std::vector<float> depth(stored), frac(stored);
    glGetNamedBufferSubData(m_heads.id(), 0, GLsizeiptr(pixels * sizeof(GLuint)), heads.data());
    if (stored) {
        const GLsizeiptr bytes = GLsizeiptr(stored * 4);
        glGetNamedBufferSubData(m_nodeDepth.id(), 0, bytes, depth.data());
        glGetNamedBufferSubData(m_nodePart.id(), 0, bytes, part.data());
        glGetNamedBufferSubData(m_nodeFrac.id(), 0, bytes, frac.data());
        glGetNamedBufferSubData(m_nodeColor.id(), 0, bytes, color.data());
        glGetNamedBufferSubData(m_next.id(), 0, bytes, next.data());
    }
    // Linked lists -> compressed rows: count per pixel, prefix sum, fill; both walks in parallel.
    FragmentLists lists;
    lists.width = width;
    lists.offsets.assign(pixels + 1, 0);
    auto walk = [&](std::uint32_t head, auto&& visit) {
        std::size_t guard = 0;
        for (std::uint32_t n = head; n != kEndOfList && n < stored && guard <= stored; n = next[n], ++guard) visit(n);
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels, 4096), [&](const auto& range) {
        for (std::size_t p = range.begin(); p != range.end(); ++p) {
            std::uint64_t count = 0;
            walk(heads[p], [&](std::uint32_t) { ++count; });
            lists.offsets[p + 1] = count;
        }
    });
    for (std::size_t p = 0; p < pixels; ++p) lists.offsets[p + 1] += lists.offsets[p];
    lists.fragments.resize(lists.offsets[pixels]);
    colors.resize(lists.fragments.size());
    // Each list sorted front to back once, here: Algorithm 1 needs the order, and the resolve
    // blends the same sorted lists (on the CPU, see render()). Sorted as (depth, part, node)
    // keys gathered into a per-range buffer: no indirect loads in the comparisons, and equal
    // depths stay in a fixed order.
    struct SortEntry {
        std::uint64_t key;  // monotone depth bits << 32 | part
        std::uint32_t node;
        bool operator<(const SortEntry& o) const { return key != o.key ? key < o.key : node < o.node; }
    };
    auto depthKey = [](float d) {
        std::uint32_t bits;
        std::memcpy(&bits, &d, sizeof bits);
        return bits & 0x80000000u ? ~bits : bits | 0x80000000u;  // IEEE order as unsigned order
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels, 1024), [&](const auto& range) {
        std::vector<SortEntry> entries;
        for (std::size_t p = range.begin(); p != range.end(); ++p) {
            entries.clear();
            walk(heads[p], [&](std::uint32_t n) {
                entries.push_back({std::uint64_t(depthKey(depth[n])) << 32 | part[n], n});
            });
            std::sort(entries.begin(), entries.end());
            std::uint64_t i = lists.offsets[p];
            for (const SortEntry& e : entries) {
                lists.fragments[i] = {depth[e.node], part[e.node], frac[e.node]};
                colors[i++] = color[e.node];
            }
        }
    });
    return lists;
}

void OpacityRenderer::render(const FrameSetup& setup, FrameImages& out, StageSink& timer) {
    resize(setup.width, setup.height);
    m_stats = {};
    m_stats.parts = m_parts.partCount();
    m_stats.capacity = m_capacity;
    // image.samples: the sample positions of core/tiling.h (a centred Hammersley set, box
    // filter), as every other technique gets them from TiledTechnique, but one optimisation per
    // frame: the system comes from the lists of the sample nearest the pixel centre, and every
    // sample is blended with the same displayed opacities (the paper's multi-sampled lines,
    // Sect. 4.2, share one fragment list per pixel; a solve per sample would also move the
    // displayed opacities once per sample).
    const std::vector<glm::vec2> offsets = sampleOffsets(m_samples);
    const std::size_t centre = nearestToCentre(offsets);
    auto sampleSetup = [&](std::size_t s) {
        FrameSetup ss = setup;
        if (m_samples > 1) ss.window = ImageWindow{setup.width, setup.height, 0, 0, offsets[s]};
        return ss;
    };
    const FrameSetup centreSetup = sampleSetup(centre);
    m_geometry.setFrame(centreSetup, m_lighting);
    m_geometry.computeBillboards(timer);
    if (m_gbuffer) m_gbuffer->render(m_geometry, centreSetup, timer);

    // 1. Fragment lists, 2. h_ij from the sorted lists, 3. the solve: optimise().
    std::vector<std::uint32_t> colors;  // per sorted fragment, packUnorm4x8 straight RGBA
    const FragmentLists lists = sortedLists(centreSetup, colors, timer);
    optimise(lists, centreSetup, timer);

    // 4. Resolve (on the CPU), then the AOVs.
    auto t0 = std::chrono::steady_clock::now();
    timer.begin("resolve");
    resolve(lists, colors, setup.width, setup.height, out);
    timer.end();
    m_stats.resolveMs = msSince(t0);
    if (m_samples > 1) addOtherSamples(setup, offsets, centre, out, timer);
    glDepthMask(GL_TRUE);

    readAovs(setup, out, timer);
}

void OpacityRenderer::addOtherSamples(const FrameSetup& setup, const std::vector<glm::vec2>& offsets,
                                      std::size_t centre, FrameImages& out, StageSink& timer) {
    // The stats' fragment counts stay those of the lists the system came from.
    const std::uint64_t fragments = m_stats.fragments, overflow = m_stats.overflow;
    FrameImages sample;
    for (std::size_t s = 0; s < offsets.size(); ++s) {
        if (s == centre) continue;
        FrameSetup ss = setup;
        ss.window = ImageWindow{setup.width, setup.height, 0, 0, offsets[s]};
        m_geometry.setFrame(ss, m_lighting);
        m_geometry.computeBillboards(timer);
        std::vector<std::uint32_t> sampleColors;
        const FragmentLists sampleLists = sortedLists(ss, sampleColors, timer);
        timer.begin("resolve");
        resolve(sampleLists, sampleColors, setup.width, setup.height, sample);
        // Sums of the samples, divided once at the end (as TiledTechnique does).
        for (std::size_t i = 0; i < out.rgba.size(); ++i) out.rgba[i] += sample.rgba[i];
        timer.end();
    }
    m_stats.fragments = fragments;
    m_stats.overflow = overflow;
    const float invSamples = 1.0f / float(offsets.size());
    for (float& v : out.rgba) v *= invSamples;
}

void OpacityRenderer::readAovs(const FrameSetup& setup, FrameImages& out, StageSink& timer) {
    const auto t0 = std::chrono::steady_clock::now();
    timer.begin("readback");
    if (m_gbuffer) {
        m_gbuffer->readAovs(out);
    } else {
        const std::size_t pixels = std::size_t(setup.width) * setup.height;
        out.depth.assign(pixels, std::numeric_limits<float>::infinity());
        out.normal.assign(3 * pixels, 0.0f);
        out.id.assign(pixels, kBackgroundId);
    }
    out.ao.clear();
    timer.end();
    m_stats.resolveMs += msSince(t0);
}

FragmentLists OpacityRenderer::sortedLists(const FrameSetup& setup, std::vector<std::uint32_t>& colors,
                                           StageSink& timer) {
    const std::uint64_t produced = buildFragmentLists(setup, timer);
    const auto t0 = std::chrono::steady_clock::now();
    timer.begin("lists_sort");
    FragmentLists lists =
        readAndSortLists(setup.width, setup.height, std::min<std::uint64_t>(produced, m_capacity), colors);
    timer.end();
    m_stats.readbackMs += msSince(t0);
    return lists;
}

Eigen::VectorXd OpacityRenderer::displayedAfter(const Eigen::VectorXd& solution) const {
    if (m_displayed.size() != solution.size()) return solution;
    return m_displayed + double(m_spec.blend) * (solution - m_displayed);
}

void OpacityRenderer::optimise(const FragmentLists& lists, const FrameSetup& setup, StageSink& timer) {
    // The first frame always solves its own system: there is nothing to show before it, and a
    // single frame is the same with and without render.opacity.pipeline.
    if (!m_spec.pipeline || m_displayed.size() == 0) {
        FrameOcclusion occlusion;
        assembleOcclusion(lists, setup, occlusion, timer, m_stats);
        solve(lists, setup, occlusion, timer, m_stats, m_solution);
        // Displayed opacities follow the solution at rate `blend`.
        m_displayed = displayedAfter(m_solution);
        m_lastSolve = m_stats;
        m_lastSolve.solvedFrame = setup.frame;
        m_stats.solvedFrame = setup.frame;
        return;
    }
    // render.opacity.pipeline (Günther et al. 2013, Sect. 4.4): H is assembled and the system
    // solved on a worker thread while frames keep coming; each frame fades the displayed
    // opacities toward the latest finished solution. A finished solve is taken here, and the
    // worker, when idle, starts on this frame's lists, warm started from the latest solution. One
    // worker does assembly and solve in turn (the paper runs them on two threads).
    timer.begin("pipeline");
    using namespace std::chrono_literals;
    if (m_pending.valid() && m_pending.wait_for(0s) == std::future_status::ready) {
        PipelinedSolve done = m_pending.get();
        m_solution = std::move(done.solution);
        m_lastSolve = done.stats;
        m_lastSolve.solvedFrame = done.frame;
    }
    if (!m_pending.valid()) {
        m_pending = std::async(std::launch::async, [this, lists, setup, start = m_solution]() mutable {
            PipelinedSolve result;
            result.frame = setup.frame;
            CpuStageTimer worker;  // the frame's StageSink belongs to the render thread
            FrameOcclusion occlusion;
            assembleOcclusion(lists, setup, occlusion, worker, result.stats);
            solve(lists, setup, occlusion, worker, result.stats, start);
            result.solution = std::move(start);
            return result;
        });
    }
    timer.end();
    // This frame's stats report the latest finished solve (solvedFrame says of which frame).
    const FrameStats listStats = m_stats;
    m_stats = m_lastSolve;
    m_stats.parts = listStats.parts;
    m_stats.capacity = listStats.capacity;
    m_stats.fragments = listStats.fragments;
    m_stats.overflow = listStats.overflow;
    m_stats.listsMs = listStats.listsMs;
    m_stats.readbackMs = listStats.readbackMs;
    m_displayed = displayedAfter(m_solution);
}

std::uint64_t OpacityRenderer::buildFragmentLists(const FrameSetup& setup, StageSink& timer) {
    const auto t0 = std::chrono::steady_clock::now();
    timer.begin("fragment_lists");
    // Blending stays on while fragment shaders have side effects: llvmpipe keeps a pixel's
    // fragments in primitive order only then. The build pass writes 0, which "under" leaves
    // unchanged.
    beginUnderCompositing(m_framebuffer.id(), setup.width, setup.height);
    const GLuint zeroCount = 0, end = kEndOfList;
    glNamedBufferSubData(m_counter.id(), 0, sizeof(GLuint), &zeroCount);
    glClearNamedBufferData(m_heads.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &end);
    const GLuint b = m_buildProgram.id();
    glProgramUniform1ui(b, uniformLocation(b, "uImageWidth"), GLuint(setup.width));
    glProgramUniform1ui(b, uniformLocation(b, "uCapacity"), GLuint(m_capacity));
    glProgramUniform1ui(b, uniformLocation(b, "uPartsPerLine"), GLuint(m_parts.partsPerLine));
    glUseProgram(b);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVertexPartW, m_vertexPartW.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kListHeads, m_heads.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kFragmentDepths, m_nodeDepth.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kFragmentParts, m_nodePart.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kFragmentFracs, m_nodeFrac.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kFragmentColors, m_nodeColor.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kFragmentNext, m_next.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kFragmentCounter, m_counter.id());
    m_geometry.draw(0, m_geometry.segmentCount());
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint produced = 0;
    glGetNamedBufferSubData(m_counter.id(), 0, sizeof(GLuint), &produced);
    m_stats.fragments = produced;
    m_stats.overflow = produced > m_capacity ? produced - m_capacity : 0;
    timer.setItems(produced);
    timer.end();
    m_stats.listsMs = msSince(t0);
    if (m_stats.overflow)
        std::cerr << "warning: opacity optimization, frame " << setup.frame << ": " << m_stats.overflow << " of "
                  << produced << " fragments did not fit the fragment pool of " << m_capacity
                  << " nodes (render.memory_budget_mb) and were left out of h_ij and the image\n";
    return produced;
}

OpacityWeights OpacityRenderer::weights() const {
    return {m_spec.p, m_spec.q, m_spec.r, m_spec.s, m_spec.lambda};
}

void OpacityRenderer::assembleOcclusion(const FragmentLists& lists, const FrameSetup& setup, FrameOcclusion& occlusion,
                                        StageSink& timer, FrameStats& stats) {
    // render.opacity.occlusion_scale < 1: H from the lists of a subsample of the pixels, as if
    // rasterized at that fraction of the width and height (core/occlusion_matrix.h,
    // subsampleLists). The resolve still blends all full-size lists: it needs them sorted
    // anyway, so a second, smaller list pass would only add a GL pass and a read-back.
    const std::size_t n = m_parts.partCount();
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    timer.begin("h_assembly");
    occlusion.scaled = m_spec.occlusionScale < 1.0f;
    if (occlusion.scaled) occlusion.scaledLists = subsampleLists(lists, setup.height, double(m_spec.occlusionScale));
    const FragmentLists& occlusionLists = occlusion.lists(lists);
    const FragmentLists& scaledLists = occlusion.scaledLists;
    stats.occlusionWidth = occlusion.scaled ? scaledLists.width : setup.width;
    stats.occlusionHeight =
        occlusion.scaled ? int(scaledLists.pixelCount() / std::size_t(scaledLists.width)) : setup.height;
    stats.occlusionFragments = occlusionLists.fragments.size();
    std::uint64_t pairs = 0;
    for (std::size_t p = 0; p < occlusionLists.pixelCount(); ++p) {
        const std::uint64_t length = occlusionLists.offsets[p + 1] - occlusionLists.offsets[p];
        pairs += length > 1 ? length * (length - 1) / 2 : 0;
    }
    stats.pairs = pairs;
    // Assembled H costs Algorithm 1's pairs once plus ~its non-zeros per product; from the lists
    // a product costs the fragments. Auto assembles while the pairs are at most
    // kAssembleBelowPairsPerFragment per fragment: at 8k parts (9.8 per fragment) assembling took
    // 13x the list operator's set-up and saved 15 ms of CPU per product, ~0.35 s per solve
    // (`tubecast_opacity_bench --parts 2000,8000 --occlusion both` times both on the same system);
    // at 2k parts (2.4) the two are about even.
    constexpr double kAssembleBelowPairsPerFragment = 4;
    using Occlusion = OpacityOptimizationSpec::Occlusion;
    occlusion.fromFragments = m_spec.occlusion == Occlusion::Fragments ||
                              (m_spec.occlusion == Occlusion::Auto && m_spec.dropBelow == 0 && m_spec.dumpDir.empty() &&
                               double(pairs) > kAssembleBelowPairsPerFragment *
                                                   double(std::max<std::size_t>(1, occlusionLists.fragments.size())));
    stats.fromFragments = occlusion.fromFragments;
    if (occlusion.fromFragments) {
        m_assembler.release();
        SparseMatrixF().swap(m_recycledH);
        occlusion.energy.emplace(std::make_shared<const FragmentOcclusion>(occlusionLists, n), m_importance, m_parts,
                                 weights());
    } else {
        // Into the last frame's arrays (Eigen's SparseMatrix has no move assignment; swap is O(1)).
        occlusion.h.swap(m_recycledH);
        m_assembler.assemble(occlusionLists, n, occlusion.h);
        stats.hNonZeros = std::size_t(occlusion.h.nonZeros());
    }
    timer.setItems(occlusion.fromFragments ? occlusionLists.fragments.size() : stats.hNonZeros);
    timer.end();
    stats.assemblyMs = msSince(t0);
    stats.assemblyCpuMs = cpuMsSince(c0);
}

void OpacityRenderer::solve(const FragmentLists& lists, const FrameSetup& setup, FrameOcclusion& occlusion,
                            StageSink& timer, FrameStats& stats, Eigen::VectorXd& solution) {
    const std::size_t n = m_parts.partCount();
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    timer.begin("solve");
    std::optional<OpacityEnergy>& energy = occlusion.energy;
    if (!energy) energy.emplace(std::move(occlusion.h), m_importance, m_parts, weights(), m_spec.dropBelow);
    stats.energyMs = msSince(t0);
    stats.energyCpuMs = cpuMsSince(c0);
    const Eigen::VectorXd lo = Eigen::VectorXd::Zero(Eigen::Index(n)), hi = Eigen::VectorXd::Ones(Eigen::Index(n));
    if (solution.size() != Eigen::Index(n)) solution = hi;
    QpSolverOptions options;
    options.tolerance = m_spec.tolerance;
    options.maxIterations = m_spec.maxIterations;
    if (m_spec.coarseScale > 0.0f) {
        // render.opacity.coarse_scale: first the system of the lists subsampled at that scale
        // (much cheaper products), from the previous solution, then the real one
        // from its solution. The real solve stops at the same tolerance on the same energy; the
        // coarse one only moves its starting point (at 8k-128k parts the cold solve took 15-22
        // products instead of 24-39 after coarse lists of 320 px; warm frames at 8k did not gain:
        // `tubecast_fragment_occlusion_bench FILE --coarse C --next FILE.frame1`).
        const FragmentLists coarseLists = subsampleLists(lists, setup.height, double(m_spec.coarseScale));
        const OpacityEnergy coarse(std::make_shared<const FragmentOcclusion>(coarseLists, n), m_importance, m_parts,
                                   weights());
        stats.coarse = solveBoundedQp(coarse, coarse.linearTerm(), lo, hi, solution, options);
        solution = stats.coarse.x;
    }
    stats.solve = solveBoundedQp(*energy, energy->linearTerm(), lo, hi, solution, options);
    solution = stats.solve.x;
    timer.setItems(std::uint64_t(stats.solve.iterations));
    timer.end();
    stats.solveMs = msSince(t0);
    stats.solveCpuMs = cpuMsSince(c0);
    if (!stats.solve.converged)
        std::cerr << "warning: opacity optimization, frame " << setup.frame << ": solver stopped after "
                  << stats.solve.iterations << " iterations at projected-gradient norm " << stats.solve.residual
                  << " (render.opacity.tolerance " << m_spec.tolerance << ")\n";
    if (m_sink) {
        // The displayed opacities this solution gives (set by optimise() right after).
        const Eigen::VectorXd displayed = displayedAfter(solution);
        m_sink({setup.frame, &*energy, occlusion.fromFragments ? nullptr : &energy->occlusion(),
                &occlusion.lists(lists), &m_parts, &m_importance, &solution, &displayed, &stats.solve});
    }
    if (!occlusion.fromFragments) energy->releaseOcclusion(m_recycledH);
}

void OpacityRenderer::resolve(const FragmentLists& lists, const std::vector<std::uint32_t>& colors, int w, int hgt,
                              FrameImages& out) const {
    // Each sorted list blended front to back with the displayed opacities, on the CPU. The lists
    // are in memory and sorted already; a full-screen GL pass walking them was what llvmpipe is
    // slowest at (SSBO loads in a data-dependent loop: ~10 s for 0.57 M fragments at 1280x1024
    // under load, against ~0.1 s for the same pass without the loop), and this loop costs a few
    // ns per fragment. Matches the shader arithmetic: unpackUnorm4x8, "under".
    const std::size_t n = m_parts.partCount();
    out.width = w;
    out.height = hgt;
    out.rgba.assign(4 * std::size_t(w) * hgt, 0.0f);
    std::vector<float> opacity(std::max<std::size_t>(1, n), 1.0f);
    for (std::size_t i = 0; i < n; ++i) opacity[i] = float(m_displayed[Eigen::Index(i)]);
    tbb::parallel_for(tbb::blocked_range<int>(0, hgt, 16), [&](const auto& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
                float sum[4] = {0, 0, 0, 0};
                for (std::uint64_t k = lists.offsets[p]; k < lists.offsets[p + 1]; ++k) {
                    const LineFragmentW& f = lists.fragments[k];
                    float a = opacity[f.part];
                    if (f.frac > 0.0f) a += (opacity[f.part + 1] - a) * f.frac;
                    const std::uint32_t c = colors[k];
                    const float alpha = float(c >> 24) / 255.0f * a, weight = (1.0f - sum[3]) * alpha;
                    sum[0] += weight * float(c & 0xFFu) / 255.0f;
                    sum[1] += weight * float((c >> 8) & 0xFFu) / 255.0f;
                    sum[2] += weight * float((c >> 16) & 0xFFu) / 255.0f;
                    sum[3] += weight;
                    if (sum[3] >= 1.0f) break;  // nothing behind can show
                }
                // Image rows top to bottom (GL's are bottom to top, as readTextureFlipped turns them).
                float* o = &out.rgba[4 * (std::size_t(hgt - 1 - y) * std::size_t(w) + std::size_t(x))];
                for (int ch = 0; ch < 4; ++ch) o[ch] = sum[ch];
            }
    });
}

nlohmann::json OpacityRenderer::describe() const {
    const char* importance[] = {"constant", "length", "curvature", "attribute"};
    nlohmann::json j = {
        {"technique", "rasterized"},
        {"transparency", "opacity_optimization"},
        {"cap_clipping", m_capClipping},
        {"billboards", m_geometry.describeBillboards()},
        {"billboard_shape", m_geometry.describeBillboardShape()},
        {"parts", m_parts.partCount()},
        {"segments_per_line", m_spec.segmentsPerLine},
        {"weights", {{"p", m_spec.p}, {"q", m_spec.q}, {"r", m_spec.r}, {"s", m_spec.s}, {"lambda", m_spec.lambda}}},
        {"importance", importance[int(m_spec.importance)]},
        {"fragment_pool_nodes", m_capacity},
        {"solver",
         "gradient projection + CG on the free set, diag + smoothness (tridiagonal) preconditioner, "
         "warm started"},
        {"h_assembly", "CPU, oneTBB (Algorithm 1 on read-back sorted per-pixel lists, image tiles)"},
        {"occlusion", m_spec.occlusion == OpacityOptimizationSpec::Occlusion::Assembled   ? "assembled"
                      : m_spec.occlusion == OpacityOptimizationSpec::Occlusion::Fragments ? "fragments"
                                                                                          : "auto"},
        {"drop_below", m_spec.dropBelow},
        {"occlusion_scale", m_spec.occlusionScale},
        {"coarse_scale", m_spec.coarseScale},
        {"resolve", "CPU (the sorted lists blended front to back)"},
        {"pipeline", m_spec.pipeline},
        {"samples", m_samples},
        {"halo", !m_geometry.haloDefines().empty()},
        {"aovs_from", m_gbuffer ? "G-buffer pass (first surface of the union of tubes)" : "none"}};
    if (m_spec.importance == OpacityOptimizationSpec::Importance::Attribute)
        j["importance_attribute"] = m_spec.attribute;
    return j;
}

}  // namespace tc::gl
