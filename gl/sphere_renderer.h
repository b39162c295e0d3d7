#pragma once
// Particles as sphere glyphs (Staib, Grottel & Gumhold 2015), render.technique "spheres":
//   transparent ("object_order"): per frame, power-distance sort keys (shaders/sphere_sort_keys.comp)
//     and the GPU radix sort (gl/radix_sort.h), then one billboard per particle in that order
//     (shaders/sphere_billboard.vert), the density model's analytic opacity per fragment
//     (shaders/sphere.frag) blended front to back into an RGBA32F target. With chunks > 1, the
//     early-z approximation of Sect. 5.2: after each chunk a full-screen pass gives depth 0 to
//     pixels whose alpha exceeds the threshold and later chunks skip them by early depth tests.
//   opaque: the same billboards, first hit by depth test, Blinn-Phong.
// Billboards are point sprites by default (render.spheres.primitive "points": one vertex per
// particle); a frame in which some sphere needs a larger point than the implementation draws is
// drawn again with two triangles per particle ("quads", which can also be chosen outright).
// Per-particle data lives in SSBOs (centre+radius, colour, id); upload() replaces it for a new
// data frame of a time series.
#include <memory>
#include <optional>

#include "core/region.h"
#include "core/scene.h"
#include "core/styled_particles.h"
#include "core/technique.h"
#include "core/technique_registry.h"
#include "gl/objects.h"
#include "gl/quad_indices.h"
#include "gl/radix_sort.h"

namespace tc::gl {

class SphereAmbient;

class SphereRenderer final : public Technique {
public:
    // Compiles the programs and uploads `particles`. Needs a current context. Throws InputError
    // for a transparency mode spheres do not have. `region` (data-parallel rendering,
    // core/region.h): a sphere is drawn only where its entry point along the ray lies in
    // region.box; the depth range and the AO grid come from region.dataBounds, and with
    // region.reduceDensity the AO volume holds every rank's spheres (SphereAmbient::voxelize).
    static std::unique_ptr<SphereRenderer> create(const Scene& scene, const StyledParticles& particles,
                                                  const RegionSetup& region = {});
    // Per-pixel GPU memory for `scene` (resize()): the opaque pass's colour, normal + depth, id and
    // depth; transparent also the blend colour and depth.
    static PixelBuffers pixelBuffers(const Scene& scene);
    ~SphereRenderer() override;

    // Replaces the particles (a new data frame), timed as stage "upload" of `timer`.
    void upload(const StyledParticles& particles, StageSink& timer);

    void render(const FrameSetup& setup, FrameImages& out, StageSink& timer) override;
    nlohmann::json describe() const override;

    // Fragments the early-z chunks skipped in the last transparent frame (0 with one chunk), and
    // the fragments that were shaded. For tests and timings.csv (stage "early_z" items).
    std::uint64_t lastSkippedFragments() const { return m_lastSkipped; }
    std::uint64_t lastShadedFragments() const { return m_lastShaded; }
    // Whether the last frame was drawn with quads (chosen, or points fell back to them).
    bool lastFrameUsedQuads() const { return m_lastUsedQuads; }

private:
    SphereRenderer() = default;
    void uploadBuffers(const StyledParticles& particles);
    void resize(int width, int height);
    // Uploads the frame uniform block (gl/frame_uniforms.h) of `setup`, with the spheres' far depth.
    void setFrame(const FrameSetup& setup);
    // The density model, point size and AO uniforms of a draw program.
    void setUniforms(GLuint program) const;
    void sort(StageSink& timer);
    // The draw programs of one billboard primitive.
    struct Programs {
        bool points = false;
        Program transparent, opaque, count;
    };
    Programs compilePrograms(bool points) const;
    const Programs& quads();  // compiled on first use when points are the default
    void drawRange(const Programs& programs, std::size_t first, std::size_t count) const;
    void drawFrame(const FrameSetup& setup, const Programs& programs, StageSink& timer, const std::string& suffix);
    void renderTransparent(const FrameSetup& setup, const Programs& programs, StageSink& timer,
                           const std::string& suffix);
    void renderOpaque(const FrameSetup& setup, const Programs& programs, Framebuffer& target, StageSink& timer,
                      const std::string& stage);

    bool m_opaque = false;
    bool m_aovs = false;
    RegionSetup m_region;  // depth/normal/id requested: an opaque pass supplies them in transparent mode
    SpheresSpec m_spheres;
    LightingSpec m_lighting;
    std::size_t m_count = 0;
    Bounds m_bounds;
    float m_maxRadius = 0;
    Buffer m_centerRadius, m_colors, m_ids, m_keys, m_order;
    Buffer m_frameUniforms;
    std::vector<std::string> m_defines;  // AO defines shared by the draw programs
    Programs m_pointPrograms, m_quadPrograms;
    Program m_earlyZProgram, m_sortKeyProgram;
    Buffer m_oversized;  // points: spheres too large for a point sprite in the last draw
    float m_maxPointSize = 1.0f;
    bool m_lastUsedQuads = false;
    std::optional<RadixSort> m_radixSort;
    std::unique_ptr<SphereAmbient> m_ambient;
    VertexArray m_emptyVao;
    QuadIndices m_quads;  // the quad path's triangles
    Query m_samplesQuery;
    std::vector<Query> m_chunkQueries;
    int m_width = 0, m_height = 0;
    Texture m_color, m_depth, m_opaqueColor, m_normalDepth, m_id, m_opaqueDepth;
    Framebuffer m_blendTarget, m_opaqueTarget;
    std::uint64_t m_lastSkipped = 0, m_lastShaded = 0;
    bool m_voxelsStale = true;  // the particles changed since the last voxelization
};

}  // namespace tc::gl
