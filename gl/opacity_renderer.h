#pragma once
// Opacity optimization (Günther, Rössl & Theisel 2013) as render.transparency
// "opacity_optimization": every segment of every line is drawn, each part's opacity minimises the
// bounded least-squares energy of core/opacity_optimization.h for the current view.
//
// Per frame: (1) "fragment_lists": the rounded cones' transparent fragments (shaders/
// transparent_fragment.glsl) go into per-pixel linked lists (A-buffer: global atomic counter,
// per-pixel heads; shaders/opacity_build.frag) with depth, colour and the blending parameter w;
// (2) "lists_sort" + "h_assembly": the lists are read back and sorted per pixel on the CPU
// (oneTBB), and Algorithm 1 builds h_ij from them (or from every (1/s)-th pixel's list in x and y
// with render.opacity.occlusion_scale s < 1) (core/occlusion_matrix.h), or, with
// render.opacity.occlusion "fragments", products with H are formed from the lists by prefix sums
// and H is never built (core/fragment_occlusion.h); (3) "solve": the
// bounded QP, warm started from the previous frame's solution (h_ij below
// render.opacity.drop_below left out); displayed opacities move toward the solution by
// render.opacity.blend per frame; (4) "resolve": the same sorted lists are blended front to back
// on the CPU with alpha = style alpha * lerp(a_i, a_i+1, frac(w)).
//
// render.opacity.pipeline: from the second frame on, stages 2 and 3 run on a worker thread on the
// lists of the frame that was current when it became idle; each frame takes a finished solution
// and fades the displayed opacities toward it (Günther et al. 2013, Sect. 4.4).
//
// image.samples: the lists of every sample position are built, sorted and blended in turn; the
// system of each frame is solved once, from the sample nearest the pixel centre.
//
// Memory: the node pool (20 bytes a node in five 4-byte arrays) gets what render.memory_budget_mb
// leaves after the colour target and the heads, and at most GL_MAX_SHADER_STORAGE_BLOCK_SIZE / 4
// nodes (33.5 M on llvmpipe); fragments past it are counted, not stored, and reported
// (lastStats().overflow, stderr): never a crash.
#include <Eigen/Core>
#include <functional>
#include <future>
#include <optional>

#include "core/occlusion_matrix.h"
#include "core/opacity_optimization.h"
#include "core/opacity_system.h"
#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/technique.h"
#include "core/technique_registry.h"
#include "gl/gbuffer_pass.h"
#include "gl/line_geometry.h"
#include "gl/objects.h"

namespace tc::gl {

class OpacityRenderer final : public Technique {
public:
    struct FrameStats {
        std::size_t parts = 0;
        std::uint64_t fragments = 0;  // produced by the lines (stored + overflow)
        std::uint64_t overflow = 0;   // not stored: the node pool was full
        std::size_t capacity = 0;     // nodes that fit
        std::size_t hNonZeros = 0;    // 0 when H came from the fragment lists
        bool fromFragments = false;   // products with H from the lists (render.opacity.occlusion)
        std::uint64_t pairs = 0;      // pairs Algorithm 1 visits (sum over pixels of L(L-1)/2)
        // The lists H came from (render.opacity.occlusion_scale): their image size and fragments.
        int occlusionWidth = 0, occlusionHeight = 0;
        std::size_t occlusionFragments = 0;
        QpResult solve;   // iterations, products, residual (solve.x: the solution)
        QpResult coarse;  // the solve of render.opacity.coarse_scale's lists (0 products: off)
        double listsMs = 0, readbackMs = 0, assemblyMs = 0, solveMs = 0, resolveMs = 0;
        double energyMs = 0;  // of solveMs: building the energy from H (assembled occlusion only)
        // The frame whose lists the reported solve came from: this frame, or with
        // render.opacity.pipeline the latest solve the worker finished (the stats above from
        // h_assembly on are that solve's).
        int solvedFrame = 0;
        // Process CPU time (all threads) of the same stages: what A/B runs compare on a shared machine.
        double assemblyCpuMs = 0, solveCpuMs = 0, energyCpuMs = 0;
    };
    using SystemSink = std::function<void(const OpacitySystem&)>;

    // `vertexAttribute`: one value per vertex of the attribute render.opacity.importance names
    // (required then, InputError otherwise). `sink` gets every frame's system (may be empty).
    static std::unique_ptr<OpacityRenderer> create(const Scene& scene, const StyledLines& lines,
                                                   const std::vector<float>* vertexAttribute = nullptr,
                                                   SystemSink sink = {});

    // Per-pixel GPU memory for `scene` besides the node pool, which takes what
    // render.memory_budget_mb leaves: the colour target, the list heads, the AOV G-buffer.
    static PixelBuffers pixelBuffers(const Scene& scene);

    void render(const FrameSetup& setup, FrameImages& out, StageSink& timer) override;
    nlohmann::json describe() const override;

    const FrameStats& lastStats() const { return m_stats; }
    const Eigen::VectorXd& displayedOpacities() const { return m_displayed; }
    const std::vector<double>& importance() const { return m_importance; }
    const OpacityParts& parts() const { return m_parts; }

private:
    explicit OpacityRenderer(LineGeometry geometry) : m_geometry(std::move(geometry)) {}
    void resize(int width, int height);
    // The stages of render(), in order.
    // "fragment_lists": the lines' transparent fragments into the per-pixel lists; returns how
    // many were produced (stored + overflow).
    std::uint64_t buildFragmentLists(const FrameSetup& setup, StageSink& timer);
    // "lists_sort": reads the lists back, sorts each front to back and returns them in compressed
    // rows for Algorithm 1, with each sorted fragment's packed colour in `colors` for the resolve.
    FragmentLists readAndSortLists(int width, int height, std::uint64_t stored, std::vector<std::uint32_t>& colors);
    // One frame's occlusion: the lists H is formed from (the sorted lists, or their subsample at
    // render.opacity.occlusion_scale) and either the assembled H or the energy over the lists.
    struct FrameOcclusion {
        bool scaled = false;
        FragmentLists scaledLists;
        bool fromFragments = false;  // products with H from the lists (render.opacity.occlusion)
        SparseMatrixF h;             // assembled H, handed to the energy (its arrays, not a copy)
        std::optional<OpacityEnergy> energy;
        const FragmentLists& lists(const FragmentLists& sorted) const { return scaled ? scaledLists : sorted; }
    };
    // "fragment_lists" and "lists_sort" of one sample position.
    FragmentLists sortedLists(const FrameSetup& setup, std::vector<std::uint32_t>& colors, StageSink& timer);
    // "h_assembly" and "solve" of the frame's lists: the displayed opacities for its resolve.
    void optimise(const FragmentLists& lists, const FrameSetup& setup, StageSink& timer);
    // "h_assembly": H (or the energy over the lists) from the sorted lists.
    void assembleOcclusion(const FragmentLists& lists, const FrameSetup& setup, FrameOcclusion& occlusion,
                           StageSink& timer, FrameStats& stats);
    // "solve": the bounded QP, warm started from `solution`, which it overwrites; hands the system
    // to the sink. Touches no GL (render.opacity.pipeline runs it on a worker thread).
    void solve(const FragmentLists& lists, const FrameSetup& setup, FrameOcclusion& occlusion, StageSink& timer,
               FrameStats& stats, Eigen::VectorXd& solution);
    // The displayed opacities after this frame's fade toward `solution` (render.opacity.blend).
    Eigen::VectorXd displayedAfter(const Eigen::VectorXd& solution) const;
    // "resolve": blends the sorted lists with the displayed opacities into out.rgba (w x hgt).
    void resolve(const FragmentLists& lists, const std::vector<std::uint32_t>& colors, int w, int hgt,
                 FrameImages& out) const;
    // image.samples > 1: lists and resolve of every sample but the centre one (whose lists the
    // system came from), all blended with the same displayed opacities; averages them into out.
    void addOtherSamples(const FrameSetup& setup, const std::vector<glm::vec2>& offsets, std::size_t centre,
                         FrameImages& out, StageSink& timer);
    // "readback": depth, normal and id AOVs from the G-buffer (or empty ones without it).
    void readAovs(const FrameSetup& setup, FrameImages& out, StageSink& timer);
    OpacityWeights weights() const;

    OpacityOptimizationSpec m_spec;
    bool m_capClipping = true;
    std::size_t m_memoryBudgetBytes = 0;
    int m_samples = 1;  // image.samples, taken here (the frame loop does not wrap this technique)
    LightingSpec m_lighting;
    SystemSink m_sink;

    LineGeometry m_geometry;
    std::optional<GBufferPass> m_gbuffer;
    OpacityParts m_parts;
    std::vector<double> m_importance;
    Eigen::VectorXd m_solution, m_displayed;  // empty before the first frame
    // Assembled H: the assembly's buffers and the last frame's H arrays, refilled every frame
    // instead of allocated and first-touched anew (page faults: core/occlusion_matrix.h).
    OcclusionAssembler m_assembler;
    SparseMatrixF m_recycledH;
    FrameStats m_stats;

    Program m_buildProgram;
    Buffer m_vertexPartW, m_heads, m_nodeDepth, m_nodePart, m_nodeFrac, m_nodeColor, m_next, m_counter;
    int m_width = 0, m_height = 0;
    std::size_t m_capacity = 0;
    Texture m_color;
    Framebuffer m_framebuffer;

    // render.opacity.pipeline: the solve running on the worker thread, and the stats of the latest
    // finished one. Last, so it is destroyed (waiting for the worker) before what the worker uses.
    struct PipelinedSolve {
        int frame = 0;
        Eigen::VectorXd solution;
        FrameStats stats;
    };
    FrameStats m_lastSolve;
    std::future<PipelinedSolve> m_pending;
};

}  // namespace tc::gl
