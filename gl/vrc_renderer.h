#pragma once
// Voxel-based line ray casting (VRC; Kanzler, Rautenhaus & Westermann 2019) as a render technique:
// the view-independent voxel model of the lines (core/vrc_model.h, built once per dataset on the
// CPU) is uploaded as two SSBOs (per-voxel header, linear piece array) and traversed per pixel by
// one compute dispatch (shaders/vrc_raycast.comp) that writes colour and the AOVs. Opaque, or
// semi-transparent with front-to-back compositing along the ray (no fragment sorting, no
// per-pixel lists). Ambient occlusion and soft shadows cone-trace the density volume of
// gl/ambient_occlusion.h (the tube volume per voxel: Eq. 1's length x opacity weighted by the
// cross-section); hard shadows trace a ray against the representative lines of one LoD level
// (core/vrc_representative.h). The paper's own variants (render.vrc.ao.method density_rays /
// precomputed, render.vrc.shadow_mode density_cone / hard_tubes) read the Eq. 1 pyramid of the
// model or its pieces instead (shaders/vrc_lighting.glsl, uploadLighting).
#include <optional>
#include <string>
#include <vector>

#include "core/halo.h"
#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/technique.h"
#include "core/technique_registry.h"
#include "core/vrc_model.h"
#include "core/vrc_packed.h"
#include "gl/ambient_occlusion.h"
#include "gl/objects.h"

namespace tc::gl {

// The GPU build path: the same model as tc::buildVrcModel (without the LoD pyramid), built by
// compute shaders and read back. Per polyline, shaders/vrc_build.comp counts the pieces, an
// exclusive prefix sum (shaders/vrc_scan.comp) gives each polyline its slots, a second walk writes
// the pieces with their voxel ids (the walk in double precision, unfused: the CPU's arithmetic);
// the stable GPU radix sort (gl/radix_sort.h) orders (voxel id, slot) pairs, and
// shaders/vrc_gather.comp gathers the pieces and writes the headers and neighbourhood bits. The
// polyline vertex ranges are found on the CPU (one pass over the flags); the copies
// (VrcBuildOptions::dilate) are added on the CPU by tc::dilateVrcModel after the read-back. Needs a current context;
// `gpuMs` (if not null) receives the wall time from upload to the finished model on the GPU.
VrcModel buildVrcModelGpu(const StyledLines& lines, const VrcBuildOptions& options, double* gpuMs = nullptr);

// The Eq. 1 pyramid of `model` (model.lod, which must be built) as one mipmapped R16F 3D texture
// (shaders/vrc_lighting.glsl, uVrcDensity): mip l is level l; level 0 is padded with empty voxels
// to `size`, a multiple of 2^(levels - 1) per axis, so that every mip halves evenly (levels is at
// most 7 and at most the pyramid's levels). Needs a current context.
struct VrcDensityTexture {
    Texture texture;
    glm::ivec3 size{0};
    int levels = 0;
};
VrcDensityTexture uploadVrcDensity(const VrcModel& model);

// Per-voxel spherical AO (Kanzler et al. 2019, Sec. 5.3, second approach) of `model` at its voxel
// centres: shaders/vrc_ao_precompute.comp, `rays` density rays over the sphere up to
// `radiusVoxels`, one R16F 3D texture of the model grid (1 where no piece is in a voxel's 3x3x3
// block). `header` is the model's voxel headers as uploaded. `ms` (if not null) receives the GPU
// wall time. Needs a current context.
Texture precomputeVrcSphereAo(const VrcModel& model, const Buffer& header, const VrcDensityTexture& density, int rays,
                              float radiusVoxels, double* ms = nullptr);

class VrcRenderer final : public Technique {
public:
    // Builds the model (render.vrc; on the GPU or the CPU by render.vrc.build), uploads it and
    // compiles the ray caster. Needs a current context.
    // With render.vrc.neighbors off the model gets copies (core/vrc_model.h). Quantized pieces are
    // read through one texture buffer of up to GL_MAX_TEXTURE_BUFFER_SIZE pieces (128 Mi on
    // llvmpipe); exact pieces are split over up to kMaxPieceBlocks shader storage blocks of at most
    // GL_MAX_SHADER_STORAGE_BLOCK_SIZE each (128 MiB on llvmpipe; the cap is per block, not in
    // total). Only a model with copies that neither holds falls back to neighbour tests
    // (describe(): copies_did_not_fit).
    static std::unique_ptr<VrcRenderer> create(const Scene& scene, const StyledLines& lines);
    // Per-pixel GPU memory: the colour, normal + depth, id and AO images.
    static PixelBuffers pixelBuffers(const Scene& scene);
    // Same, from a model built elsewhere (tests, the GPU build path). `maxBlockBytes` > 0 caps the
    // bytes of one piece block below the GL limit (tests force several blocks on a small model);
    // throws tc::InputError if the model needs more than kMaxPieceBlocks blocks.
    static std::unique_ptr<VrcRenderer> create(const Scene& scene, const StyledLines& lines, const VrcModel& model,
                                               std::size_t maxBlockBytes = 0);

    // Most shader storage blocks the piece array is split over (VRC_PIECE_BLOCKS of
    // shaders/vrc_raycast.comp).
    static constexpr int kMaxPieceBlocks = 8;
    // How the ray caster reads a piece array (shaders/vrc_raycast.comp): quantized pieces through
    // one texture buffer over the whole array when it has at most `maxTexels` pieces
    // (GL_MAX_TEXTURE_BUFFER_SIZE; one piece per texel), which no storage block limit caps;
    // otherwise (exact pieces, or more pieces than texels) as `blocks` shader storage blocks of
    // `perBlock` pieces (the largest power of two within `maxBlockBytes`) each. fits(): the ray
    // caster can read it.
    struct PieceStorage {
        bool texture = false;
        std::size_t blocks = 0, perBlock = 0;
        bool fits() const { return texture || blocks <= std::size_t(kMaxPieceBlocks); }
    };
    static PieceStorage pieceStorage(std::size_t pieces, std::size_t bytesPerPiece, bool quantized,
                                     std::size_t maxBlockBytes, std::size_t maxTexels);
    // Where render.vrc.build builds the model on a GL whose GL_RENDERER is `glRenderer`: "gpu" and
    // "cpu" as asked; "auto" on the GPU (Kanzler et al. 2019, Sec. 3.3) except on a software
    // rasterizer, which runs the compute shaders on the CPU build's cores (docs/performance.md,
    // "Model build: CPU against GPU").
    static bool buildsOnGpu(VrcSpec::Build build, const std::string& glRenderer);

    // Most LoD levels (kVrcLodMaxLevels of shaders/vrc_lod.glsl; resolution 1024 has 11).
    static constexpr int kMaxLodLevels = 12;
    // With render.vrc.lod: count the ray caster's LoD samples per level from the next frame on
    // (recompiles the ray caster with VRC_LOD_STATS; an atomic add per sample). lodSamples():
    // the last frame's samples at level 0, 1, ... (kMaxLodLevels entries) and, last, the rays
    // that entered the LoD volume; describe() reports them too. For tests and benchmarks.
    void enableLodStats();
    const std::vector<std::uint32_t>& lodSamples() const { return m_lodSamples; }
    // The LoD volume is sampled at `level` or coarser (0, the default: as the rules say). With
    // opacity_start 0 a ray renders the volume at that level alone: the benchmark's per-level
    // rows (tests/bench/vrc_bench.cpp).
    void setLodMinLevel(int level) { m_lodMinLevel = level; }

    void render(const FrameSetup& setup, FrameImages& out, StageSink& timer) override;
    nlohmann::json describe() const override;

private:
    VrcRenderer() = default;
    void resize(int width, int height);
    // The parts of create(): the brick occupancy of empty space skipping, the piece array in
    // blocks (throws tc::InputError past kMaxPieceBlocks), the hard shadows' representative
    // lines, and the ray caster's defines for what was uploaded.
    void uploadBricks(const VrcModel& model);
    void uploadPieces(const VrcModel& model, std::size_t maxBlockBytes);
    // pieceStorage of `model` under this context's limits (`maxBlockBytes` > 0: a smaller block).
    static PieceStorage pieceStorageOf(const VrcModel& model, std::size_t maxBlockBytes);
    // render.vrc.encoding "paper": the packed model (core/vrc_packed.h) as the header buffers, one
    // GL_R32UI texture buffer of the piece words and, with the id image requested, the global ids.
    void uploadPaper(const VrcPackedModel& packed, bool globalIds);
    void uploadShadowLines(const VrcModel& model);
    // The LoD volume (core/vrc_model.h buildVrcLodVolume) as the atlas of shaders/vrc_lod.glsl.
    void uploadLodVolume(const VrcModel& model);
    void setLodUniforms(GLuint program) const;
    nlohmann::json lodDescription() const;
    std::vector<std::string> rayCasterDefines() const;
    // The paper's AO and shadows (shaders/vrc_lighting.glsl): the Eq. 1 pyramid, the precomputed
    // AO, and their defines.
    void uploadLighting(const VrcModel& model, bool aoEnabled, std::vector<std::string>& defines);
    void applyLightingUniforms(GLuint program) const;

    VrcSpec m_spec;
    bool m_transparent = false;
    std::optional<LineHalo> m_halo;  // style.halo (drawn by the transparent ray caster)
    LightingSpec m_lighting;
    std::optional<AmbientOcclusion> m_ao;  // AO and/or soft shadows
    bool m_aoEnabled = false;
    float m_shadowDistance = 0, m_shadowStartOffset = 0;

    // Model geometry and statistics (the pieces themselves live on the GPU only).
    glm::ivec3 m_size{0};
    glm::vec3 m_origin{0.0f};
    float m_voxelSize = 0, m_maxRadius = 0;
    int m_quantization = 0;
    std::size_t m_pieces = 0, m_copies = 0, m_bytesPerPiece = 0, m_modelBytes = 0, m_lodBytes = 0, m_segments = 0,
                m_rawBytes = 0;
    double m_buildMs = 0, m_uploadMs = 0;
    bool m_gpuBuild = false;         // the model came from buildVrcModelGpu (render.vrc.build)
    bool m_copiesDidNotFit = false;  // render.vrc.neighbors off, but the copies exceeded one SSBO

    // Hard shadows: the representative lines of one LoD level (2 x vec4 per voxel).
    Buffer m_shadowLines;
    glm::ivec3 m_shadowGridSize{0};
    float m_shadowVoxelSize = 0;
    int m_shadowLevel = 0;
    double m_representativeMs = 0;

    // The paper's lighting (uploadLighting): Eq. 1 pyramid, precomputed spherical AO.
    VrcDensityTexture m_eq1Density;
    Texture m_aoVolume;
    float m_aoStrength = 1;
    double m_aoPrecomputeMs = 0;
    // LoD (render.vrc.lod): all levels side by side along x in one RGBA16F 3D texture.
    Texture m_lodAtlas;
    glm::ivec3 m_lodAtlasSize{0};
    std::vector<float> m_lodAtlasX;  // x texel of each level's border
    std::vector<glm::ivec3> m_lodLevelSizes;
    std::size_t m_lodBytes3d = 0;
    double m_lodBuildMs = 0;
    Buffer m_lodStats;
    std::vector<std::uint32_t> m_lodSamples;
    int m_lodMinLevel = 0;

    Buffer m_header;  // compact16: (offset, count) per voxel; paper: the first piece per voxel
    // render.vrc.encoding: the packed encoding is in use (m_paper), or why it was not
    // (m_encodingFallback, empty when compact16 was asked for or paper is in use).
    bool m_paper = false;
    std::string m_encodingFallback;
    VrcPaperLayout m_paperLayout;
    std::uint32_t m_paperRadiusCode = 0;
    std::vector<std::uint32_t> m_palette;
    int m_paletteColors = 0, m_paletteMaxError = 0;
    bool m_paletteExact = true;
    std::size_t m_headerBytes = 0, m_globalIdBytes = 0;
    double m_packMs = 0;
    Buffer m_paperCounts;       // 1-byte counts, four voxels per word
    Buffer m_globalIdBuffer;    // per piece, the polyline id (only with the id image)
    Texture m_globalIdTexture;  // GL_R32UI over m_globalIdBuffer
    // The piece array, read through m_pieceTexture (quantized pieces: GL_RGBA32UI over the whole
    // buffer; m_pieceBlockCount 0) or bound as m_pieceBlockCount shader storage blocks (ranges) of
    // 2^m_blockShift pieces (pieceStorage).
    Buffer m_pieceBuffer;
    std::size_t m_pieceBlockCount = 0, m_piecesInBuffer = 0;
    Texture m_pieceTexture;
    int m_blockShift = 0;
    Buffer m_bricks;  // empty space skipping: 1 per brick of 4^3 voxels that can hold a surface
    glm::ivec3 m_brickGridSize{1};
    std::vector<std::string> m_defines;  // the ray caster's, kept for enableLodStats
    Program m_program;
    Buffer m_frameUniforms;  // gl/frame_uniforms.h, set per frame
    int m_width = 0, m_height = 0;
    Texture m_color, m_normalDepth, m_id, m_aoImage;
};

}  // namespace tc::gl
