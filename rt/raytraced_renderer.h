#pragma once
// render.technique "raytraced": the tubes of the rasterized path, ray traced on the CPU with
// Embree 3 round linear curves (rt/embree_lines.h) over 8x8 pixel tiles with oneTBB; tiles into
// which no tube can project (rt/tile_cover.h) are background without a ray. Same camera rays
// (core/camera.h), shading (core/shading.h), colour pipeline and AOVs as the GL techniques, so
// switching technique gives the same picture up to float differences:
// - Opaque: the first hit along each pixel-centre ray. render.raytraced.surface "embree" (the
//   default): Embree's round-curve hit as it is (distance, geometric normal, segment), the same
//   surface as the CPU reference's to float rounding (tests/unit/raytraced_test.cpp bounds the
//   difference). "exact": Embree finds the segment; its depth and normal are then recomputed with
//   core/rounded_cone.h on that segment and its polyline neighbours, by the rule of
//   core/cpu_reference.h (visible t = tIn if > 0 else tOut if > 0, the nearest wins, ties to the
//   lower segment), so depth / normal / id equal the CPU reference's bit for bit wherever Embree
//   and the reference agree on the segment; that costs about a fifth of the frame on a dense set
//   (docs/performance.md, "Ray tracing on the CPU"). Embree's round curves do not show the inner
//   wall to a ray that starts inside a tube: a frame whose rays may start in one (the eye in a
//   tube, or a tube across an orthographic image rectangle; an Embree point query per frame)
//   takes "exact". A region (below) always uses "exact".
// - Transparent (render.transparency other than "opaque"): every tube entry along the ray, one
//   contribution per front-facing hit, composited front to back in exact depth order ("under",
//   premultiplied, as core/transparent_reference.h), stopping once the accumulated alpha reaches
//   render.raytraced.alpha_cutoff (1 = exact). With render.cap_clipping the segments of a polyline
//   are joined into one tube (Embree neighbour flags: no internal surfaces, so a ray enters it once
//   per crossing, the semantics cap clipping gives the GL path); without, every rounded cone is
//   entered on its own (beads at joints, as the GL path without cap clipping). Hits of adjacent
//   segments within a small epsilon of each other (a ray through the shared rim at a joint) count
//   once. A back-facing hit counts only when the ray origin lies inside that segment's rounded
//   cone (an eye inside a tube sees its inner wall, as the references). The depth / normal / id
//   AOVs describe the first contributing hit.
// - Halos (style.halo; core/halo.h, the CPU twin of the GL path's ring): the BVH holds every
//   segment's rounded cone grown by the ring as a closed cone of its own (no neighbour flags), and
//   each front-facing hit of one (a back-facing one when the ray starts inside it) names a
//   segment whose fragment is computed exactly as the CPU reference's (core/transparent_reference.h
//   segmentFragmentOf: the tube entry after cap clipping, else the halo fragment, whose depth lies
//   behind the ring's surface). Fragments are composited in (depth, segment) order once no later
//   hit can give one in front of them: a hit at t has its fragment no nearer than t - (1 + width)
//   r_max / dot(dir, forward) (the ray's point nearest the axis is behind the ring's entry and
//   within (1 + width) r_max of the axis). Always a transparent mode (opaque lines: alpha 1
//   composites to the nearest fragment). "ray_traced" AO traces against a second BVH of the tubes.
// - Region (data-parallel rendering, core/region.h): only contributions whose entry point lies in
//   the region box. Opaque: the nearest visible t (the rule above, per segment) whose point is in
//   the box, so the regions' depth images Z-composite to the whole frame's; transparent: the hits
//   whose point is in the box, composited "under" per region and across regions in view order.
//   Rays are restricted to the box's parameter interval (with a margin, so the joint duplicate
//   test sees the hit before the box face).
// - AO (render.ao): "cone_traced" samples the CPU twin of the GL density volume with the algorithm
//   of shaders/cone_tracing.glsl (rt/cone_traced_ao.h); "ray_traced" shoots render.ao.samples
//   stratified cosine-weighted hemisphere rays per shaded point (rt/ray_traced_ao.h).
// Of the depth / normal / id AOVs only those scene.output asks for are written (the frame loop
// clears the flags of AOVs no output reads); the others are left empty (core/frame_images.h
// KeptAovs).
// Images are deterministic: every pixel is computed independently of the thread that runs it.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/halo.h"
#include "core/region.h"
#include "core/scene.h"
#include "core/stage_sink.h"
#include "core/styled_lines.h"
#include "core/technique.h"
#include "core/tiling.h"
#include "core/transparent_reference.h"
#include "rt/hit_collector.h"
#include "rt/primary_rays.h"
#include "rt/tile_cover.h"

namespace tc::rt {

class EmbreeLines;
class AoEstimator;

class RaytracedRenderer final : public Technique {
public:
    // Builds the BVH (once per dataset) and, with render.ao, the AO data. Keeps a copy of `lines`.
    // Throws InputError for transparency modes the ray tracer does not implement. `region`:
    // data-parallel rendering (see above; AO through region.reduceDensity and region.dataBounds).
    static std::unique_ptr<RaytracedRenderer> create(const Scene& scene, const StyledLines& lines,
                                                     const RegionSetup& region = {});
    ~RaytracedRenderer() override;

    // Renders one frame into `out` (allocated to width x height): rgba linear premultiplied,
    // depth / normal / id as core/frame_images.h, ao (opaque with AO enabled: the factor at the
    // visible surface, 1 on background). Stages: "raytrace" (items = Embree hits processed).
    // `window`: the part of the full image and the sample position this target is (core/tiling.h).
    void render(const Camera& camera, int width, int height, FrameImages& out, StageSink& sink,
                const ImageWindow& window = {}) const;

    // The Technique interface: render() above with the setup's camera, size and window.
    void render(const FrameSetup& setup, FrameImages& out, StageSink& sink) override {
        render(setup.camera, setup.width, setup.height, out, sink, setup.window);
    }
    nlohmann::json describe() const override;

    // How opaque primary rays traverse the BVH (rt/primary_rays.h; transparent rays always go one
    // at a time: their filter callback collects hits per ray). Images do not depend on it.
    void setTraversal(Traversal t) { m_traversal = t; }
    Traversal traversal() const { return m_traversal; }

    // How many hits a transparent ray collects per traversal (rt/hit_collector.h): 0 = the default
    // (hitsPerPass of the alpha cutoff and the lines' mean opacity), 1 = one traversal per hit as a
    // plain rtcIntersect1 loop would. Images do not depend on it; for tests and
    // tests/bench/raytraced_bench.cpp.
    void setHitsPerPass(int k) { m_hitsPerPass = k > 0 ? std::min(k, kMaxHitsPerPass) : m_defaultHitsPerPass; }
    int hitsPerPass() const { return m_hitsPerPass; }

    // Total Embree hits the last render() composited or skipped (transparent: those in front of
    // the cutoff; opaque: 1 per covered pixel), for tests and timings.
    std::uint64_t lastHitCount() const { return m_lastHits; }
    // Whether the last opaque render() used the exact surface (render.raytraced.surface "exact",
    // a region, or rays that may start inside a tube; see the header), for tests and timings.
    bool lastFrameExactSurface() const { return m_lastExactSurface; }

private:
    RaytracedRenderer() = default;
    struct PixelContext;
    // The visible surface the CPU reference's rule gives for Embree's hit `hit` (see the header):
    // t, segment and outward normal, over the hit segment and its polyline neighbours; with
    // `inRegion`, only points in the region box count. False when no candidate qualifies
    // (`anyCandidate` then says whether some did before the region test).
    struct Surface {
        float t = 0;
        std::uint32_t segment = 0;
        glm::vec3 normal{0.0f};
    };
    bool visibleSurface(const Ray& ray, const FirstHit& hit, bool inRegion, Surface& s, bool& anyCandidate) const;
    void shadeOpaque(PixelContext& px, const FirstHit& hit, bool exactSurface) const;
    // Whether a primary ray of this frame may start inside a tube (conservative); `radiusScale`
    // grows every tube (the halo's ring).
    bool originsMayStartInTubes(const Camera& camera, const ImageWindow& window, int width, int height,
                                float radiusScale = 1.0f) const;
    void shadeSurface(PixelContext& px, const Surface& s) const;
    // Region opaque rays: the first Embree hit whose surface (visibleSurface) lies in the box,
    // traced from the box's entry; false: background.
    bool regionSurface(PixelContext& px, Surface& s) const;
    void shadeTransparent(PixelContext& px) const;
    // Transparent with halos (see the header); `view`: the camera's, for the rings' depth;
    // `originsInside`: this frame's rays may start inside a grown cone, so fragments are
    // composited only after the last hit.
    void shadeTransparentHalo(PixelContext& px, const FragmentView& view, bool originsInside) const;
    // The part of `ray` a region traces: its interval in the box, widened by the margin.
    RayInterval regionRayInterval(const Ray& ray) const;
    // [tnear, tfar] a transparent ray traces: all of it, or the region's part; false when a
    // region's part is empty (the pixel gets nothing).
    bool tracedSpan(const Ray& ray, float& tnear, float& tfar) const;

    StyledLines m_lines;
    // What shading reads per hit, by segment: its polyline (the id AOV, the joint and neighbour
    // tests) in one array, so it costs one memory access instead of two dependent ones (segment ->
    // vertex -> polyline); and, when every vertex has the same colour (a constant style.color),
    // that colour, so opaque shading reads no vertex data at all. The hit's line data is a cache
    // miss on a dense set (about half the shading's time, `perf annotate`), which the bare Embree
    // program of scripts/bench/embree_baseline.cpp pays once per pixel too.
    std::vector<std::uint32_t> m_segmentPolyline;
    bool m_uniformColor = false;
    glm::vec3 m_color{0.0f};
    LightingSpec m_lighting;
    KeptAovs m_aovs;  // the first-surface AOVs scene.output asks for; the others stay empty
    bool m_transparent = false;
    bool m_joinNeighbours = true;
    bool m_capClipping = true;  // render.cap_clipping (halos: the planes of segmentFragmentOf)
    bool m_exactSurface = false;
    float m_alphaCutoff = 0.99f;
    float m_jointEpsilon = 0;  // world units: hits of adjacent segments this close count once
    RegionBox m_region;
    std::unique_ptr<EmbreeLines> m_embree;  // with halos: the grown cones
    std::optional<LineHalo> m_halo;
    std::unique_ptr<EmbreeLines> m_aoEmbree;  // halos and "ray_traced" AO: the tubes themselves
    std::unique_ptr<AoEstimator> m_ao;
    Traversal m_traversal = Traversal::Packet16;
    int m_hitsPerPass = 16, m_defaultHitsPerPass = 16;
    SceneBounds m_bounds;  // of the BVH: tiles whose rays miss it are background (forEachTile)
    TileCover m_cover;     // and the tiles it marks empty per frame (rt/tile_cover.h)
    mutable std::uint64_t m_lastHits = 0;
    mutable bool m_lastExactSurface = false;
};

}  // namespace tc::rt
