#pragma once
// The line set on the GPU and the one way every rasterized line pass draws it: SSBOs for
// per-vertex data and the segment index buffer (bindings in shaders/line_buffers.glsl), the
// frame uniform block (gl/frame_uniforms.h) and the billboard pre-pass
// (shaders/billboard_pass.comp). Passes own their programs and targets; this owns the data.
#include <cstddef>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "core/halo.h"
#include "core/region.h"
#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/technique.h"
#include "gl/objects.h"
#include "gl/quad_indices.h"

namespace tc::gl {

// The defines that switch a line shader's halo ring on (shaders/transparent_fragment.glsl,
// shaders/vrc_raycast.comp): HALO, HALO_WIDTH, HALO_DEPTH and HALO_COLOR (linear RGB).
std::vector<std::string> haloDefines(const LineHalo& halo);

class LineGeometry {
public:
    // Uploads positions+radius, colours, polyline ids, vertex flags and the segment index
    // buffer. Needs a current context. `region` (data-parallel rendering, core/region.h): with a
    // box, every draw program clips fragments to it (REGION_CLIP); the depth range comes from its
    // data bounds.
    // `shape`: the billboard construction of every program of this geometry (core/billboard.h).
    static LineGeometry create(const StyledLines& lines, BillboardPath path, const RegionSetup& region = {},
                               BillboardShape shape = BillboardShape::Gross2020);
    // Bytes create() uploads for `lines` besides the per-frame billboard buffers: positions +
    // radius, colours, polyline ids and flags per vertex, two vertex indices per segment.
    static std::size_t uploadBytes(const StyledLines& lines);

    std::size_t segmentCount() const { return m_segmentCount; }
    BillboardPath billboardPath() const { return m_path; }
    // Defines selecting the billboard shape, for every program that builds billboards
    // (shaders/billboard.glsl): BILLBOARD_RECTANGLE for BillboardShape::Rectangle.
    std::vector<std::string> billboardDefines() const {
        return m_shape == BillboardShape::Rectangle ? std::vector<std::string>{"BILLBOARD_RECTANGLE"}
                                                    : std::vector<std::string>{};
    }
    // Where billboards are built, for run.json.
    const char* describeBillboards() const;
    // render.billboard_shape's value, for run.json.
    const char* describeBillboardShape() const {
        return m_shape == BillboardShape::Rectangle ? "rectangle" : "gross2020";
    }

    const Buffer& positionRadiusBuffer() const { return m_positionRadius; }
    const Buffer& segmentVerticesBuffer() const { return m_segmentVertices; }

    // Binds the line SSBOs (gl/bindings.h, the line group) and this geometry's frame uniforms.
    void bind() const;
    // Whether the transparent fragment shaders clip at the joint planes (render.cap_clipping):
    // the planes are built once per segment with the billboard (shaders/segment_varyings.glsl),
    // so every program of this geometry reads uCapClipping of the frame uniforms.
    void setCapClipping(bool enabled) { m_capClipping = enabled; }
    // Depth-dependent halos (style.halo; shaders/transparent_fragment.glsl): billboards grow by
    // the halo ring and every program compiled after this call gets the HALO defines (ring width
    // and depth offset in tube radii, linear RGB colour). Recompiles the billboard pre-pass; call
    // before compiling the passes' programs. The depth range grows by the halo's depth offset.
    void enableHalo(const LineHalo& halo);
    // Uploads this frame's (or tile's) uniform block: frameUniforms(setup, lighting) with the
    // lines' uViewProj, uFarDepth, uCapClipping and region box, and binds it. Every pass of the frame reads it,
    // so call it first.
    void setFrame(const FrameSetup& setup, const LightingSpec& lighting);
    // Linear depth scale: gl_FragDepth = view depth / farDepth(setup).
    float farDepth(const FrameSetup& setup) const;

    // Compiles a program drawing the lines' billboards with `fragmentShader`, for this
    // geometry's billboard path; `defines` go to every stage, and REGION_CLIP when the geometry
    // has a region box (the fragment shaders then drop what enters the ray outside it).
    Program compileDrawProgram(const char* fragmentShader, std::vector<std::string> defines = {}) const;
    const std::vector<std::string>& haloDefines() const { return m_haloDefines; }
    // REGION_CLIP when the geometry has a region box, for full-screen passes that test hits.
    std::vector<std::string> regionDefines() const {
        return m_region.unbounded() ? std::vector<std::string>{} : std::vector<std::string>{"REGION_CLIP"};
    }
    // Builds this frame's billboards (BillboardPath::Compute; no-op otherwise) as stage
    // "billboards" of `timer`, for the camera of setFrame.
    void computeBillboards(StageSink& timer) const;
    // Dispatches the billboard compute `program` (billboard_pass.comp) over the draw slots
    // [firstSlot, firstSlot + count), for the camera of setFrame; the caller adds the memory
    // barrier.
    void buildBillboards(GLuint program, std::size_t firstSlot, std::size_t count) const;
    // Draws `count` segments starting at draw slot `first` with the bound program. When the
    // program was compiled with DRAW_ORDER, slot i draws segment drawOrder[i] (binding::kDrawOrder).
    void draw(std::size_t first, std::size_t count) const;

private:
    LineGeometry() = default;

    BillboardPath m_path = BillboardPath::Compute;
    BillboardShape m_shape = BillboardShape::Gross2020;
    std::size_t m_segmentCount = 0;
    float m_maxRadius = 0;  // of the whole dataset (RegionSetup::maxRadiusOr): the depth range
    bool m_capClipping = false;
    Bounds m_bounds;  // of the whole dataset (RegionSetup::boundsOr): the depth range
    RegionBox m_region;
    std::vector<std::string> m_haloDefines;  // enableHalo
    Buffer m_positionRadius, m_colors, m_polylineIds, m_flags, m_segmentVertices, m_billboardCorners;
    Buffer m_segmentRecords;  // BillboardPath::Compute: what the fragment shaders need per segment
    Buffer m_frameUniforms;   // gl/frame_uniforms.h, set per frame
    Program m_billboardProgram;
    VertexArray m_emptyVao;  // core profile needs a bound VAO even when vertices are pulled
    QuadIndices m_quads;     // the billboard quads' triangles (not with BillboardPath::Geometry)
};

}  // namespace tc::gl
