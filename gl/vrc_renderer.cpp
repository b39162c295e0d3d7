#include "gl/vrc_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "core/voxel_density.h"
#include "core/vrc_representative.h"
#include "gl/bindings.h"
#include "gl/frame_uniforms.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/line_geometry.h"
#include "gl/radix_sort.h"
#include "gl/shader_library.h"
#include "gl/techniques.h"

namespace tc::gl {

namespace {

// Bricks of empty space skipping are kBrick^3 voxels; the ray caster's work groups kGroupSize^2
// pixels. Both reach shaders/vrc_raycast.comp as defines (VRC_BRICK, VRC_GROUP_SIZE).
constexpr int kBrick = 4;
constexpr int kGroupSize = 8;

void dispatch1D(GLuint program, std::size_t count) {
    const std::size_t groups = (count + 63) / 64;
    const std::size_t gx = std::min<std::size_t>(std::max<std::size_t>(groups, 1), 65535);
    glProgramUniform1ui(program, uniformLocation(program, "uCount"), GLuint(count));
    glUseProgram(program);
    glDispatchCompute(GLuint(gx), GLuint((groups + gx - 1) / gx), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

// The paper's AO and soft shadows read the Eq. 1 pyramid (shaders/vrc_lighting.glsl).
bool usesEq1Density(const Scene& scene) {
    const VrcSpec& v = scene.render.vrc;
    return (scene.render.ao.enabled && v.ao.method != VrcSpec::Ao::Method::ConeTraced) ||
           (v.shadows && v.shadowMode == VrcSpec::ShadowMode::DensityCone);
}

}  // namespace

VrcModel buildVrcModelGpu(const StyledLines& lines, const VrcBuildOptions& options, double* gpuMs) {
    VrcModel model = emptyVrcModel(lines, options);
    if (lines.positionRadius.empty()) return model;
    const DensityGrid grid = makeDensityGrid(lines.bounds, options.resolution);
    const bool quantized = options.quantization > 0;

    std::vector<glm::uvec2> ranges;
    for (std::uint32_t i = 0; i < lines.vertexCount(); ++i) {
        if (!(lines.flags[i] & FirstOfPolyline)) continue;
        std::uint32_t last = i;
        while (!(lines.flags[last] & LastOfPolyline) && last + 1 < lines.vertexCount()) ++last;
        ranges.emplace_back(i, last);
    }
    const std::size_t polylines = ranges.size();

    std::vector<std::string> defines;
    if (quantized) defines.push_back("QUANTIZED");
    auto withDefine = [&](const char* d) {
        std::vector<std::string> v = defines;
        v.push_back(d);
        return v;
    };
    const Program count = compileProgram({{GL_COMPUTE_SHADER, "vrc_build.comp"}}, withDefine("VRC_COUNT"));
    const Program write = compileProgram({{GL_COMPUTE_SHADER, "vrc_build.comp"}}, withDefine("VRC_WRITE"));
    const Program scan = compileProgram({{GL_COMPUTE_SHADER, "vrc_scan.comp"}});
    const Program gather = compileProgram({{GL_COMPUTE_SHADER, "vrc_gather.comp"}}, withDefine("VRC_GATHER"));
    const Program header = compileProgram({{GL_COMPUTE_SHADER, "vrc_gather.comp"}}, withDefine("VRC_HEADER"));
    const Program neighbours = compileProgram({{GL_COMPUTE_SHADER, "vrc_gather.comp"}}, withDefine("VRC_NEIGHBORS"));
    RadixSort sort = RadixSort::create();

    glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    const Buffer positions = makeBuffer(lines.positionRadius.size() * sizeof(glm::vec4), lines.positionRadius.data());
    const Buffer colors = makeBuffer(lines.color.size() * sizeof(glm::vec4), lines.color.data());
    const Buffer ids = makeBuffer(lines.polylineId.size() * sizeof(std::uint32_t), lines.polylineId.data());
    const Buffer rangeBuffer = makeBuffer(ranges.size() * sizeof(glm::uvec2), ranges.data());
    const Buffer counts = makeBuffer((polylines + 1) * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kPositionRadius, positions.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVertexColors, colors.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kPolylineIds, ids.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcPolylines, rangeBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcCounts, counts.id());
    const glm::dvec3 origin(grid.origin);
    for (GLuint p : {count.id(), write.id()}) {
        glProgramUniform1ui(p, uniformLocation(p, "uPolylines"), GLuint(polylines));
        glProgramUniform3i(p, uniformLocation(p, "uGridSize"), grid.size.x, grid.size.y, grid.size.z);
        glProgramUniform3d(p, uniformLocation(p, "uOrigin"), origin.x, origin.y, origin.z);
        glProgramUniform1d(p, uniformLocation(p, "uVoxelSize"), double(grid.voxelSize));
        glProgramUniform1i(p, uniformLocation(p, "uQuantization"), options.quantization);
        glProgramUniform1f(p, uniformLocation(p, "uMaxRadius"), lines.maxRadius);
    }
    const GLuint polylineGroups = GLuint((polylines + 63) / 64);
    glUseProgram(count.id());
    glDispatchCompute(polylineGroups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glProgramUniform1ui(scan.id(), uniformLocation(scan.id(), "uCount"), GLuint(polylines));
    glUseProgram(scan.id());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    std::uint32_t total = 0;
    glGetNamedBufferSubData(counts.id(), GLintptr(polylines * sizeof(std::uint32_t)), sizeof total, &total);
    if (total >= (1u << 31))
        throw InputError("render.vrc: the voxel model would hold " + std::to_string(total) +
                         " pieces, more than 2^31; lower render.vrc.resolution");

    const std::size_t pieceBytes = model.bytesPerPiece();
    const Buffer keys = makeBuffer(std::size_t(total) * 4), values = makeBuffer(std::size_t(total) * 4);
    const Buffer raw = makeBuffer(std::size_t(total) * pieceBytes);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcKeys, keys.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcValues, values.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcRawPieces, raw.id());
    glUseProgram(write.id());
    glDispatchCompute(polylineGroups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    sort.sort(keys, values, total);  // stable: (voxel id, slot) order, as the CPU's sort

    const std::size_t voxels = model.voxelCount();
    const Buffer headerBuffer = makeBuffer(voxels * sizeof(VrcVoxel), nullptr, GL_DYNAMIC_STORAGE_BIT);
    const Buffer runEnd = makeBuffer(voxels * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
    const std::uint32_t zero = 0;
    glClearNamedBufferData(headerBuffer.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glClearNamedBufferData(runEnd.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    const Buffer pieces = makeBuffer(std::size_t(total) * pieceBytes), pieceVoxel = makeBuffer(std::size_t(total) * 4);
    // The radix sort rebinds its own points (gl/bindings.h), so every gather buffer is bound anew.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcHeader, headerBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcRunEnd, runEnd.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcKeys, keys.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcValues, values.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcRawPieces, raw.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcGatheredPieces, pieces.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcPieceVoxel, pieceVoxel.id());
    for (GLuint p : {gather.id(), header.id(), neighbours.id()})
        glProgramUniform3i(p, uniformLocation(p, "uGridSize"), grid.size.x, grid.size.y, grid.size.z);
    dispatch1D(gather.id(), total);
    dispatch1D(header.id(), voxels);
    dispatch1D(neighbours.id(), voxels);
    glUseProgram(0);
    glFinish();
    if (gpuMs) *gpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    model.voxels.resize(voxels);
    glGetNamedBufferSubData(headerBuffer.id(), 0, GLsizeiptr(voxels * sizeof(VrcVoxel)), model.voxels.data());
    model.pieceVoxel.resize(total);
    glGetNamedBufferSubData(pieceVoxel.id(), 0, GLsizeiptr(std::size_t(total) * 4), model.pieceVoxel.data());
    if (quantized) {
        model.compact.resize(total);
        glGetNamedBufferSubData(pieces.id(), 0, GLsizeiptr(std::size_t(total) * pieceBytes), model.compact.data());
    } else {
        model.exact.resize(total);
        glGetNamedBufferSubData(pieces.id(), 0, GLsizeiptr(std::size_t(total) * pieceBytes), model.exact.data());
    }
    // The copies are added on the CPU (the same function as the CPU build): a per-piece mask and a
    // sort, cheap next to the walk.
    if (options.dilate) dilateVrcModel(model, options.reach);
    return model;
}

std::unique_ptr<VrcRenderer> VrcRenderer::create(const Scene& scene, const StyledLines& lines) {
    VrcBuildOptions options;
    options.resolution = scene.render.vrc.resolution;
    options.quantization = scene.render.vrc.quantization;
    // The ray caster shades with the density volume of gl/ambient_occlusion.h (see the header),
    // or with the Eq. 1 pyramid where vrc.ao.method or vrc.shadow_mode ask for the paper's lighting.
    options.lod = usesEq1Density(scene);
    // Without neighbour tests at render time, every piece is copied into the neighbours its tube
    // reaches at build time (core/vrc_model.h, Copies): the image of the neighbour tests with far
    // fewer pieces tested per voxel (docs/performance.md, "Design notes").
    options.dilate = !scene.render.vrc.neighbors;
    // With halos a piece shows in the voxels its ring reaches.
    options.reach = haloReach(scene.style.halo);
    // The GPU build (Kanzler et al. 2019, Sec. 3.3) on a hardware GL; on a software rasterizer
    // the CPU build: llvmpipe runs the compute shaders on the same cores as the CPU build, with a
    // shader compile and a read-back on top, and was not faster beyond the noise on any bench set
    // (GPU / CPU 0.87-4.6x; docs/performance.md, "Voxel ray casting"). Both give the same model
    // (tests/gl/vrc_renderer_test.cpp).
    const GLubyte* glRenderer = glGetString(GL_RENDERER);
    const bool gpuBuild =
        buildsOnGpu(scene.render.vrc.build, glRenderer ? reinterpret_cast<const char*>(glRenderer) : "");
    auto build = [&] { return gpuBuild ? buildVrcModelGpu(lines, options) : buildVrcModel(lines, options); };
    const auto t0 = std::chrono::steady_clock::now();
    VrcModel model = build();
    Scene used = scene;
    const bool tooLarge = options.dilate && !pieceStorageOf(model, 0).fits();
    if (tooLarge) {
        // The ray caster cannot read the copies (pieceStorage): neighbour tests at render time
        // instead, from the model without copies (both exact on straight tubes thinner than a
        // voxel, tests/gl/vrc_renderer_test.cpp; the 10^7-segment tornado's transparent frames
        // of the two differ by 52.8 dB PSNR).
        options.dilate = false;
        model = build();
        used.render.vrc.neighbors = true;
    }
    const auto t1 = std::chrono::steady_clock::now();
    std::unique_ptr<VrcRenderer> r = create(used, lines, model);
    r->m_buildMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
    r->m_copiesDidNotFit = tooLarge;
    r->m_gpuBuild = gpuBuild;
    return r;
}

bool VrcRenderer::buildsOnGpu(VrcSpec::Build build, const std::string& glRenderer) {
    if (build != VrcSpec::Build::Auto) return build == VrcSpec::Build::Gpu;
    return !glRenderer.empty() && !isSoftwareRasterizer(glRenderer);
}

VrcRenderer::PieceStorage VrcRenderer::pieceStorage(std::size_t pieces, std::size_t bytesPerPiece, bool quantized,
                                                    std::size_t maxBlockBytes, std::size_t maxTexels) {
    PieceStorage s;
    // An empty model still binds one (one-piece) buffer.
    pieces = std::max<std::size_t>(1, pieces);
    if (quantized && pieces <= maxTexels) {
        s.texture = true;
        return s;
    }
    // The largest power of two of pieces within one block.
    s.perBlock = 1;
    while (2 * s.perBlock * bytesPerPiece <= maxBlockBytes && s.perBlock < (std::size_t(1) << 30)) s.perBlock *= 2;
    s.blocks = (pieces + s.perBlock - 1) / s.perBlock;
    return s;
}

VrcRenderer::PieceStorage VrcRenderer::pieceStorageOf(const VrcModel& model, std::size_t maxBlockBytes) {
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    const std::size_t limit =
        maxBlockBytes > 0 ? std::min(maxBlockBytes, std::size_t(maxBlock)) : std::size_t(maxBlock);
    return pieceStorage(model.pieceCount(), model.bytesPerPiece(), model.quantization > 0, limit,
                        std::size_t(maxTexels));
}

std::unique_ptr<VrcRenderer> VrcRenderer::create(const Scene& scene, const StyledLines& lines, const VrcModel& model,
                                                 std::size_t maxBlockBytes) {
    std::unique_ptr<VrcRenderer> r(new VrcRenderer());
    r->m_spec = scene.render.vrc;
    // Halos are drawn by the transparent ray caster (opaque lines composite to the nearest hit).
    if (scene.style.halo.enabled) r->m_halo = lineHalo(scene.style.halo, scene.image.background);
    r->m_transparent = scene.render.transparency != Transparency::Opaque || r->m_halo;
    r->m_lighting = scene.lighting;
    r->m_size = model.size;
    r->m_origin = model.origin;
    r->m_voxelSize = model.voxelSize;
    r->m_maxRadius = model.maxRadius;
    r->m_quantization = model.quantization;
    r->m_pieces = model.pieceCount();
    r->m_copies = model.copies;
    r->m_bytesPerPiece = model.bytesPerPiece();
    r->m_modelBytes = model.bytes();
    r->m_lodBytes = model.lodBytes();
    r->m_segments = lines.segmentCount();
    r->m_rawBytes = LineGeometry::uploadBytes(lines);  // what the rasterized paths upload

    r->m_headerBytes = model.voxelCount() * sizeof(VrcVoxel);

    // render.vrc.encoding "paper": pack the model (core/vrc_packed.h), or say why not and keep
    // the 16-byte encoding.
    std::optional<VrcPackedModel> packed;
    if (scene.render.vrc.encoding == VrcSpec::Encoding::Paper && !model.voxels.empty()) {
        const auto tp = std::chrono::steady_clock::now();
        if (r->m_spec.neighbors) {
            // The neighbour tests blend a line once per ray interval across the 27 voxels of a
            // block, comparing line ids of different voxels: the local line ids are local to a voxel.
            r->m_encodingFallback =
                "render.vrc.neighbors: on compares line ids across voxels, which the paper's local line ids cannot";
        } else {
            VrcPackResult result = packVrcModel(model);
            GLint maxTexels = 0;
            glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
            if (!result.ok()) {
                r->m_encodingFallback = result.reason;
            } else if (result.model.bytes.size() / 4 > std::size_t(maxTexels)) {
                r->m_encodingFallback = "the packed pieces need " + std::to_string(result.model.bytes.size() / 4) +
                                        " words, more than GL_MAX_TEXTURE_BUFFER_SIZE (" + std::to_string(maxTexels) +
                                        ")";
            } else {
                packed = std::move(result.model);
            }
        }
        r->m_packMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tp).count();
        if (!packed)
            std::cerr << "warning: render.vrc.encoding \"paper\" falls back to \"compact16\": " << r->m_encodingFallback
                      << "\n";
    }

    const auto t0 = std::chrono::steady_clock::now();
    if (model.voxels.empty()) {
        // No lines: one empty voxel keeps the shader's buffers valid.
        const VrcVoxel empty{0, 0};
        r->m_header = makeBuffer(sizeof empty, &empty);
        r->m_size = glm::ivec3(1);
        r->m_voxelSize = 1;
    } else if (!packed) {
        r->m_header = makeBuffer(model.voxels.size() * sizeof(VrcVoxel), model.voxels.data());
    }
    r->uploadBricks(model);
    if (packed) {
        r->uploadPaper(*packed, scene.output.aovId);
        r->m_bytesPerPiece = std::size_t(packed->layout.bytesPerPiece());
        r->m_headerBytes = packed->headerBytes();
        r->m_modelBytes = packed->bytesTotal();
    } else {
        r->uploadPieces(model, maxBlockBytes);
    }
    glFinish();
    r->m_uploadMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    std::vector<std::string> defines = r->rayCasterDefines();
    const AoSpec& ao = scene.render.ao;
    r->m_aoEnabled = ao.enabled;
    r->m_aoStrength = ao.strength;
    const bool coneAo = ao.enabled && r->m_spec.ao.method == VrcSpec::Ao::Method::ConeTraced;
    const bool softShadows = r->m_spec.shadows && r->m_spec.shadowMode == VrcSpec::ShadowMode::Soft;
    const bool hardShadows = r->m_spec.shadows && r->m_spec.shadowMode == VrcSpec::ShadowMode::Hard;
    if (hardShadows && !model.voxels.empty()) {
        r->uploadShadowLines(model);
        defines.push_back("HARD_SHADOWS");
    }
    if (!model.voxels.empty()) r->uploadLighting(model, ao.enabled, defines);
    if ((coneAo || softShadows) && !lines.positionRadius.empty()) {
        r->m_ao = AmbientOcclusion::create(ao, lines);
        if (coneAo) defines.push_back("AMBIENT_OCCLUSION");
        if (softShadows) {
            defines.push_back("SOFT_SHADOWS");
            const glm::vec3 extent = lines.bounds.extent();
            // The cone reaches as far as the AO cones (render.ao.distance of the diagonal) and
            // starts one density voxel out (the AO start offset; self-shadowing is excluded per
            // step by shaders/cone_tracing.glsl).
            r->m_shadowDistance = ao.distance * glm::length(extent);
            r->m_shadowStartOffset = std::max({extent.x, extent.y, extent.z}) / float(std::max(ao.resolution - 1, 1));
        }
    }
    if (r->m_spec.lod.enabled && !model.voxels.empty()) {
        r->uploadLodVolume(model);
        defines.push_back("VRC_LOD");
    }
    r->m_defines = defines;
    r->m_program = compileProgram({{GL_COMPUTE_SHADER, "vrc_raycast.comp"}}, defines);
    r->resize(scene.image.width, scene.image.height);
    return r;
}

void VrcRenderer::uploadBricks(const VrcModel& model) {
    // Brick occupancy for empty space skipping (shaders/vrc_raycast.comp, BRICK_SKIP): a brick
    // of kBrick^3 voxels is empty when none of its voxels can hold a tube's surface: no pieces
    // (with copies, those are all the tubes reaching in), or with neighbour tests none in the
    // 3x3x3 block (the neighbourhood bit).
    const glm::ivec3 bricks = (m_size + kBrick - 1) / kBrick;
    std::vector<std::uint32_t> occupied(std::size_t(bricks.x) * bricks.y * bricks.z, 0u);
    const std::uint32_t mask = m_spec.neighbors ? kNeighbourhoodBit : kCountMask;
    for (std::size_t i = 0; i < model.voxels.size(); ++i) {
        if (!(model.voxels[i].count & mask)) continue;
        const glm::ivec3 b = model.coords(i) / kBrick;
        occupied[(std::size_t(b.z) * bricks.y + b.y) * bricks.x + b.x] = 1u;
    }
    if (model.voxels.empty()) occupied.assign(1, 0u);
    m_brickGridSize = bricks;
    m_bricks = makeBuffer(occupied.size() * sizeof(std::uint32_t), occupied.data());
}

void VrcRenderer::uploadPieces(const VrcModel& model, std::size_t maxBlockBytes) {
    // One buffer, read through a texture buffer or as blocks of 2^m_blockShift pieces
    // (pieceStorage): the GL caps one shader storage block (GL_MAX_SHADER_STORAGE_BLOCK_SIZE,
    // 128 MiB on llvmpipe), not the total. A piece index i lives in block i >> shift at
    // i & (2^shift - 1).
    const std::size_t bytesPerPiece = model.bytesPerPiece();
    const std::size_t pieces = model.pieceCount();
    const PieceStorage storage = pieceStorageOf(model, maxBlockBytes);
    if (!storage.fits())
        throw InputError("render.vrc: the voxel model's " + std::to_string(pieces) + " pieces need " +
                         std::to_string(storage.blocks) + " shader storage blocks of " +
                         std::to_string(storage.perBlock) + " pieces, more than " + std::to_string(kMaxPieceBlocks) +
                         "; lower render.vrc.resolution or turn render.vrc.neighbors on");
    while ((std::size_t(1) << m_blockShift) < storage.perBlock) ++m_blockShift;
    const auto* bytes = model.quantization > 0
                            ? static_cast<const unsigned char*>(static_cast<const void*>(model.compact.data()))
                            : static_cast<const unsigned char*>(static_cast<const void*>(model.exact.data()));
    // One buffer; the blocks are ranges of it (their offsets, multiples of 2^shift pieces, are
    // aligned). An empty model still binds one valid (one-piece, zero) buffer.
    m_pieceBlockCount = storage.blocks;
    m_piecesInBuffer = std::max<std::size_t>(1, pieces);
    if (pieces == 0) {
        const std::vector<unsigned char> zero(bytesPerPiece, 0);
        m_pieceBuffer = makeBuffer(zero.size(), zero.data());
    } else {
        m_pieceBuffer = makeBuffer(pieces * bytesPerPiece, bytes);
    }
    GLint alignment = 0;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &alignment);
    if (storage.blocks > 1 && (storage.perBlock * bytesPerPiece) % std::size_t(std::max(alignment, 1)) != 0)
        throw std::logic_error("VrcRenderer: piece block of " + std::to_string(storage.perBlock * bytesPerPiece) +
                               " bytes is not a multiple of GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT " +
                               std::to_string(alignment));
    // Quantized pieces are read through a texture buffer over the whole array (one piece per
    // RGBA32UI texel; shaders/vrc_raycast.comp, VRC_PIECE_TEXTURE): llvmpipe gathers a texel
    // fetch with vector code, while a storage buffer read at per-lane addresses is a loop over
    // the lanes, and the blocks needed one read per block.
    if (storage.texture) m_pieceTexture = makeBufferTexture(m_pieceBuffer, GL_RGBA32UI);
}

void VrcRenderer::uploadPaper(const VrcPackedModel& packed, bool globalIds) {
    m_paper = true;
    m_paperLayout = packed.layout;
    m_paperRadiusCode = packed.constantRadius;
    m_palette = packed.palette;
    m_paletteColors = packed.paletteSize;
    m_paletteExact = packed.paletteExact;
    m_paletteMaxError = packed.paletteMaxError;
    m_header = makeBuffer(packed.offsets.size() * sizeof(std::uint32_t), packed.offsets.data());
    const std::vector<std::uint32_t> counts = packed.countWords();
    m_paperCounts = makeBuffer(counts.size() * sizeof(std::uint32_t), counts.data());
    const std::vector<std::uint32_t> words = packed.words();
    m_pieceBuffer = makeBuffer(words.size() * sizeof(std::uint32_t), words.data());
    m_pieceTexture = makeBufferTexture(m_pieceBuffer, GL_R32UI);
    m_pieceBlockCount = 0;
    m_piecesInBuffer = packed.pieceCount;
    if (globalIds) {
        // The id image needs the polyline ids the local ids stand in for: 4 bytes per piece
        // beside the encoding, only when the id output is asked for.
        m_globalIdBytes = packed.globalIds.size() * sizeof(std::uint32_t);
        m_globalIdBuffer = makeBuffer(m_globalIdBytes, packed.globalIds.data());
        m_globalIdTexture = makeBufferTexture(m_globalIdBuffer, GL_R32UI);
    }
}

void VrcRenderer::uploadShadowLines(const VrcModel& model) {
    // Representative lines of the chosen level (core/vrc_representative.h), two vec4 per
    // voxel: a.xyz + radius, b.xyz + weight (0 = no line).
    const auto t = std::chrono::steady_clock::now();
    const std::vector<VrcRepresentativeLevel> levels = buildRepresentativeLines(model, m_spec.shadowLevel);
    const VrcRepresentativeLevel& level = levels.back();
    std::vector<glm::vec4> packed(2 * level.lines.size());
    for (std::size_t i = 0; i < level.lines.size(); ++i) {
        const VrcRepresentativeLine& l = level.lines[i];
        packed[2 * i] = glm::vec4(l.a, l.radius);
        packed[2 * i + 1] = glm::vec4(l.b, l.weight);
    }
    m_shadowLines = makeBuffer(packed.size() * sizeof(glm::vec4), packed.data());
    m_shadowGridSize = level.size;
    m_shadowVoxelSize = level.voxelSize;
    m_shadowLevel = level.level;
    m_representativeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

VrcDensityTexture uploadVrcDensity(const VrcModel& model) {
    if (model.lod.empty())
        throw std::logic_error("uploadVrcDensity: the model has no Eq. 1 pyramid (VrcBuildOptions::lod)");
    // Level 0 is padded to a multiple of 2^(levels - 1) so that GL's mips (floor(size / 2)) are
    // the pyramid's levels (ceil(size / 2), padded with zeros) texel for texel; 6 coarser levels
    // (64 voxels) keep the padding small on flat grids, and a cone wider than that reads level 6.
    VrcDensityTexture d;
    d.levels = std::min<int>(int(model.lod.size()), 7);
    const int block = 1 << (d.levels - 1);
    d.size = (model.lod[0].size + block - 1) / block * block;
    d.texture = Texture::create(GL_TEXTURE_3D);
    const GLuint tex = d.texture.id();
    glTextureStorage3D(tex, d.levels, GL_R16F, d.size.x, d.size.y, d.size.z);
    for (int l = 0; l < d.levels; ++l) {
        const glm::ivec3 s = glm::max(d.size >> l, glm::ivec3(1));
        const float zero = 0.0f;
        glClearTexImage(tex, l, GL_RED, GL_FLOAT, &zero);
        const VrcDensityLevel& level = model.lod[std::size_t(l)];
        const glm::ivec3 n = glm::min(level.size, s);
        TC_CHECK(n == level.size);
        glTextureSubImage3D(tex, l, 0, 0, 0, n.x, n.y, n.z, GL_RED, GL_FLOAT, level.density.data());
    }
    setVolumeSampling(tex, true, VolumeEdge::ZeroBorder);
    return d;
}

namespace {

void setDensityUniforms(GLuint p, const VrcDensityTexture& density) {
    glProgramUniform1i(p, uniformLocation(p, "uVrcDensity"), GLint(binding::kVrcEq1Density));
    glProgramUniform3f(p, uniformLocation(p, "uVrcDensityTexSize"), float(density.size.x), float(density.size.y),
                       float(density.size.z));
    glProgramUniform1i(p, uniformLocation(p, "uVrcDensityMaxLevel"), density.levels - 1);
}

}  // namespace

Texture precomputeVrcSphereAo(const VrcModel& model, const Buffer& header, const VrcDensityTexture& density, int rays,
                              float radiusVoxels, double* ms) {
    const Program program =
        compileProgram({{GL_COMPUTE_SHADER, "vrc_ao_precompute.comp"}}, {std::string("VRC_AO_PRECOMPUTE")});
    Texture ao = Texture::create(GL_TEXTURE_3D);
    glTextureStorage3D(ao.id(), 1, GL_R16F, model.size.x, model.size.y, model.size.z);
    // Clamped to the edge: a hit in a border voxel reads the border voxels' AO, not "unoccluded".
    setVolumeSampling(ao.id(), false, VolumeEdge::ClampToEdge);
    const GLuint p = program.id();
    setDensityUniforms(p, density);
    glProgramUniform3i(p, uniformLocation(p, "uGridSize"), model.size.x, model.size.y, model.size.z);
    glProgramUniform3fv(p, uniformLocation(p, "uGridOrigin"), 1, &model.origin[0]);
    glProgramUniform1f(p, uniformLocation(p, "uVoxelSize"), model.voxelSize);
    glProgramUniform1i(p, uniformLocation(p, "uVrcSphereRays"), rays);
    glProgramUniform1f(p, uniformLocation(p, "uVrcAoRadius"), radiusVoxels);
    glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    glBindTextureUnit(binding::kVrcEq1Density, density.texture.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcHeader, header.id());
    glBindImageTexture(binding::kVrcAoVolumeOut, ao.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16F);
    glUseProgram(p);
    glDispatchCompute(GLuint((model.size.x + 3) / 4), GLuint((model.size.y + 3) / 4), GLuint((model.size.z + 3) / 4));
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glUseProgram(0);
    glFinish();
    if (ms) *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return ao;
}

void VrcRenderer::uploadLighting(const VrcModel& model, bool aoEnabled, std::vector<std::string>& defines) {
    using Method = VrcSpec::Ao::Method;
    const bool densityAo = aoEnabled && m_spec.ao.method == Method::DensityRays;
    const bool precomputedAo = aoEnabled && m_spec.ao.method == Method::Precomputed;
    const bool densityShadows = m_spec.shadows && m_spec.shadowMode == VrcSpec::ShadowMode::DensityCone;
    if (m_spec.shadows && m_spec.shadowMode == VrcSpec::ShadowMode::HardTubes)
        defines.push_back("VRC_HARD_TUBE_SHADOWS");
    if (!densityAo && !precomputedAo && !densityShadows) return;
    m_eq1Density = uploadVrcDensity(model);
    if (densityAo) defines.push_back("VRC_DENSITY_AO");
    if (densityShadows) defines.push_back("VRC_DENSITY_SHADOWS");
    if (precomputedAo) {
        defines.push_back("VRC_PRECOMPUTED_AO");
        // The precomputation reads the 16-byte model's header (its neighbourhood bits); with the
        // packed encoding it is uploaded for this pass only.
        const Buffer compactHeader =
            m_paper ? makeBuffer(model.voxels.size() * sizeof(VrcVoxel), model.voxels.data()) : Buffer();
        m_aoVolume = precomputeVrcSphereAo(model, m_paper ? compactHeader : m_header, m_eq1Density,
                                           m_spec.ao.sphereRays, m_spec.ao.radiusVoxels, &m_aoPrecomputeMs);
    }
}

void VrcRenderer::applyLightingUniforms(GLuint p) const {
    if (m_eq1Density.texture.id() == 0) return;
    setDensityUniforms(p, m_eq1Density);
    glBindTextureUnit(binding::kVrcEq1Density, m_eq1Density.texture.id());
    glProgramUniform1f(p, uniformLocation(p, "uVrcAoRadius"), m_spec.ao.radiusVoxels);
    glProgramUniform1f(p, uniformLocation(p, "uVrcAoStrength"), m_aoStrength);
    glProgramUniform1i(p, uniformLocation(p, "uVrcAoRays"), m_spec.ao.rays);
    if (m_aoVolume.id() != 0) {
        glProgramUniform1i(p, uniformLocation(p, "uVrcAoVolume"), GLint(binding::kVrcAoVolume));
        glBindTextureUnit(binding::kVrcAoVolume, m_aoVolume.id());
    }
}

void VrcRenderer::uploadLodVolume(const VrcModel& model) {
    const auto t = std::chrono::steady_clock::now();
    const std::vector<VrcLodLevel> levels = buildVrcLodVolume(model, !m_transparent);
    if (levels.size() > std::size_t(kMaxLodLevels))
        throw std::logic_error("VrcRenderer: " + std::to_string(levels.size()) + " LoD levels, more than " +
                               std::to_string(kMaxLodLevels));
    // Levels side by side along x, each with a one-texel zero border (shaders/vrc_lod.glsl).
    glm::ivec3 atlas(0, levels[0].size.y + 2, levels[0].size.z + 2);
    m_lodAtlasX.clear();
    m_lodLevelSizes.clear();
    for (const VrcLodLevel& level : levels) {
        m_lodLevelSizes.push_back(level.size);
        m_lodAtlasX.push_back(float(atlas.x));
        atlas.x += level.size.x + 2;
    }
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSize);
    if (atlas.x > maxSize || atlas.y > maxSize || atlas.z > maxSize)
        throw InputError("render.vrc.lod: the LoD volume needs a " + std::to_string(atlas.x) + " x " +
                         std::to_string(atlas.y) + " x " + std::to_string(atlas.z) +
                         " texture, more than GL_MAX_3D_TEXTURE_SIZE " + std::to_string(maxSize) +
                         "; lower render.vrc.resolution");
    m_lodAtlasSize = atlas;
    m_lodAtlas = Texture::create(GL_TEXTURE_3D);
    glTextureStorage3D(m_lodAtlas.id(), 1, GL_RGBA16F, atlas.x, atlas.y, atlas.z);
    const float zero[4] = {0, 0, 0, 0};
    glClearTexImage(m_lodAtlas.id(), 0, GL_RGBA, GL_FLOAT, zero);
    for (std::size_t l = 0; l < levels.size(); ++l)
        glTextureSubImage3D(m_lodAtlas.id(), 0, GLint(m_lodAtlasX[l]) + 1, 1, 1, levels[l].size.x, levels[l].size.y,
                            levels[l].size.z, GL_RGBA, GL_FLOAT, levels[l].value.data());
    setVolumeSampling(m_lodAtlas.id(), false, VolumeEdge::ClampToEdge);
    m_lodBytes3d = std::size_t(atlas.x) * atlas.y * atlas.z * 8;
    m_lodBuildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

void VrcRenderer::setLodUniforms(GLuint p) const {
    if (m_lodAtlas.id() == 0) return;
    const glm::vec3 inv = 1.0f / glm::vec3(m_lodAtlasSize);
    glProgramUniform3fv(p, uniformLocation(p, "uLodAtlasInvSize"), 1, &inv[0]);
    glProgramUniform1fv(p, uniformLocation(p, "uLodAtlasX"), GLsizei(m_lodAtlasX.size()), m_lodAtlasX.data());
    glProgramUniform1i(p, uniformLocation(p, "uLodLevels"), GLint(m_lodAtlasX.size()));
    glProgramUniform1i(p, uniformLocation(p, "uLodMinLevel"), m_lodMinLevel);
    glProgramUniform1f(p, uniformLocation(p, "uLodFootprint"), m_spec.lod.pixelFootprint);
    // Opaque rays end at their first hit: only the footprint applies. opacity_start = 1 is off.
    const bool acceleration = m_transparent && m_spec.lod.opacityStart < 1.0f;
    glProgramUniform1f(p, uniformLocation(p, "uLodOpacityStart"), acceleration ? m_spec.lod.opacityStart : 2.0f);
    glBindTextureUnit(binding::kVrcLodVolume, m_lodAtlas.id());
}

void VrcRenderer::enableLodStats() {
    if (m_lodAtlas.id() == 0 || m_lodStats.id() != 0) return;
    m_defines.push_back("VRC_LOD_STATS");
    m_program = compileProgram({{GL_COMPUTE_SHADER, "vrc_raycast.comp"}}, m_defines);
    m_lodStats = makeBuffer((kMaxLodLevels + 1) * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

std::vector<std::string> VrcRenderer::rayCasterDefines() const {
    std::vector<std::string> defines;
    if (m_paper) {
        defines.push_back("VRC_PAPER");
        defines.push_back("VRC_Q " + std::to_string(m_quantization));
        defines.push_back("VRC_PAPER_BYTES " + std::to_string(m_paperLayout.bytesPerPiece()));
        defines.push_back("VRC_PAPER_BIN_BITS " + std::to_string(m_paperLayout.binBits));
        defines.push_back("VRC_PAPER_M " + std::to_string(m_paperLayout.interiorLattice));
        defines.push_back("VRC_PAPER_LINE_BITS " + std::to_string(m_paperLayout.lineBits));
        if (m_paperLayout.countBytes == 2) defines.push_back("VRC_PAPER_WIDE_COUNTS");
        if (m_paperLayout.copies) defines.push_back("VRC_PAPER_COPIES");
        if (m_paperLayout.radiusVaries) defines.push_back("VRC_PAPER_RADII");
        if (m_globalIdTexture.id() != 0) defines.push_back("VRC_GLOBAL_IDS");
    } else if (m_quantization > 0) {
        defines.push_back("QUANTIZED");
        defines.push_back("VRC_Q " + std::to_string(m_quantization));
    }
    if (m_transparent) defines.push_back("TRANSPARENT");
    if (m_halo)
        for (const std::string& d : haloDefines(*m_halo)) defines.push_back(d);
    // Only the compositing reads a hit's alpha: opaque rendering ignores the key.
    if (m_transparent && m_spec.pathLengthOpacity) defines.push_back("VRC_PATH_LENGTH_OPACITY");
    defines.push_back("BRICK_SKIP");
    defines.push_back("VRC_BRICK " + std::to_string(kBrick));
    defines.push_back("VRC_GROUP_SIZE " + std::to_string(kGroupSize));
    defines.push_back("VRC_PIECE_BLOCKS " + std::to_string(m_pieceBlockCount));
    defines.push_back("VRC_BLOCK_SHIFT " + std::to_string(m_blockShift));
    if (m_pieceTexture.id() != 0 && !m_paper) defines.push_back("VRC_PIECE_TEXTURE");
    if (m_spec.neighbors) defines.push_back("NEIGHBORS");
    return defines;
}

PixelBuffers VrcRenderer::pixelBuffers(const Scene&) {
    return {16 + 16 + 4 + 4, 0, "voxel_raycast"};  // resize(): colour, normal + depth, id, AO image
}

void VrcRenderer::resize(int width, int height) {
    if (width == m_width && height == m_height) return;
    m_width = width;
    m_height = height;
    m_color = makeTexture2D(GL_RGBA32F, width, height);
    m_normalDepth = makeTexture2D(GL_RGBA32F, width, height);
    m_id = makeTexture2D(GL_R32UI, width, height);
    m_aoImage = makeTexture2D(GL_R32F, width, height);
}

void VrcRenderer::render(const FrameSetup& setup, FrameImages& out, StageSink& timer) {
    const int w = setup.width, h = setup.height;
    resize(w, h);

    timer.begin("raycast");
    uploadFrameUniforms(m_frameUniforms, frameUniforms(setup, m_lighting));
    const GLuint p = m_program.id();
    glProgramUniform3i(p, uniformLocation(p, "uGridSize"), m_size.x, m_size.y, m_size.z);
    glProgramUniform3fv(p, uniformLocation(p, "uGridOrigin"), 1, &m_origin[0]);
    glProgramUniform1f(p, uniformLocation(p, "uVoxelSize"), m_voxelSize);
    glProgramUniform1f(p, uniformLocation(p, "uMaxRadius"), m_maxRadius);
    glProgramUniform1f(p, uniformLocation(p, "uOpacityThreshold"), m_spec.opacityThreshold);
    if (m_ao) {
        m_ao->apply(p);
        glProgramUniform1f(p, uniformLocation(p, "uShadowTanHalfAperture"),
                           std::tan(0.5f * glm::radians(m_spec.shadowApertureDeg)));
        glProgramUniform1f(p, uniformLocation(p, "uShadowDistance"), m_shadowDistance);
        glProgramUniform1f(p, uniformLocation(p, "uShadowStrength"), 1.0f);
        glProgramUniform1f(p, uniformLocation(p, "uShadowStartOffset"), m_shadowStartOffset);
    }
    applyLightingUniforms(p);
    if (m_shadowLines.id() != 0) {
        glProgramUniform3i(p, uniformLocation(p, "uShadowGridSize"), m_shadowGridSize.x, m_shadowGridSize.y,
                           m_shadowGridSize.z);
        glProgramUniform1f(p, uniformLocation(p, "uShadowVoxelSize"), m_shadowVoxelSize);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcShadowLines, m_shadowLines.id());
    }
    glProgramUniform3i(p, uniformLocation(p, "uBrickGridSize"), m_brickGridSize.x, m_brickGridSize.y,
                       m_brickGridSize.z);
    setLodUniforms(p);
    if (m_lodStats.id() != 0) {
        const std::uint32_t zero = 0;
        glClearNamedBufferData(m_lodStats.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcLodStats, m_lodStats.id());
    }
    glUseProgram(p);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcBricks, m_bricks.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcHeader, m_header.id());
    {
        const std::size_t perBlock = std::size_t(1) << m_blockShift, bytesPerPiece = m_bytesPerPiece;
        for (std::size_t b = 0; b < m_pieceBlockCount; ++b) {
            const std::size_t first = std::min(b * perBlock, m_piecesInBuffer - 1);
            const std::size_t n = std::max<std::size_t>(1, std::min(perBlock, m_piecesInBuffer - first));
            glBindBufferRange(GL_SHADER_STORAGE_BUFFER,
                              b == 0 ? binding::kVrcPieces : binding::kVrcPieceBlocks + GLuint(b - 1),
                              m_pieceBuffer.id(), GLintptr(first * bytesPerPiece), GLsizeiptr(n * bytesPerPiece));
        }
    }
    if (m_pieceTexture.id() != 0) glBindTextureUnit(binding::kVrcPieceTexels, m_pieceTexture.id());
    if (m_paper) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding::kVrcPaperCounts, m_paperCounts.id());
        glProgramUniform1uiv(p, uniformLocation(p, "uVrcPalette"), GLsizei(m_palette.size()), m_palette.data());
        glProgramUniform1ui(p, uniformLocation(p, "uVrcRadiusCode"), m_paperRadiusCode);
        if (m_globalIdTexture.id() != 0) glBindTextureUnit(binding::kVrcGlobalIds, m_globalIdTexture.id());
    }
    glBindImageTexture(binding::kVrcColor, m_color.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(binding::kVrcNormalDepth, m_normalDepth.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(binding::kVrcId, m_id.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32UI);
    glBindImageTexture(binding::kVrcAo, m_aoImage.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glDispatchCompute(GLuint((w + kGroupSize - 1) / kGroupSize), GLuint((h + kGroupSize - 1) / kGroupSize), 1);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glUseProgram(0);
    timer.setItems(std::uint64_t(w) * std::uint64_t(h));
    timer.end();
    if (m_lodStats.id() != 0) {
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        m_lodSamples.assign(kMaxLodLevels + 1, 0u);
        glGetNamedBufferSubData(m_lodStats.id(), 0, GLsizeiptr(m_lodSamples.size() * sizeof(std::uint32_t)),
                                m_lodSamples.data());
    }

    timer.begin("readback");
    const std::size_t n = std::size_t(w) * h;
    out.width = w;
    out.height = h;
    out.rgba.resize(4 * n);
    readTextureFlipped(m_color.id(), GL_RGBA, GL_FLOAT, w, h, 4, sizeof(float), out.rgba.data());
    readNormalDepthId(m_normalDepth.id(), m_id.id(), w, h, out);
    out.ao.clear();
    if (m_aoEnabled) {
        out.ao.resize(n);
        readTextureFlipped(m_aoImage.id(), GL_RED, GL_FLOAT, w, h, 1, sizeof(float), out.ao.data());
    }
    timer.end();
}

nlohmann::json VrcRenderer::lodDescription() const {
    nlohmann::json d = {
        {"levels", m_lodAtlasX.size()},
        {"pixel_footprint", m_spec.lod.pixelFootprint},
        {"opacity_start", m_transparent ? nlohmann::json(m_spec.lod.opacityStart) : nlohmann::json("opaque")},
        {"volume_mb", double(m_lodBytes3d) / (1024.0 * 1024.0)},
        {"build_ms", m_lodBuildMs}};
    // Per level: the voxels and their MB at 8 bytes (RGBA16F), the borders of the atlas excluded.
    nlohmann::json sizes = nlohmann::json::array(), mb = nlohmann::json::array();
    for (const glm::ivec3& n : m_lodLevelSizes) {
        sizes.push_back({n.x, n.y, n.z});
        mb.push_back(double(n.x) * n.y * n.z * 8.0 / (1024.0 * 1024.0));
    }
    d["level_grids"] = sizes;
    d["level_mb"] = mb;
    if (!m_lodSamples.empty()) {
        d["samples_per_level"] = std::vector<std::uint32_t>(m_lodSamples.begin(), m_lodSamples.end() - 1);
        d["rays"] = m_lodSamples.back();
    }
    return d;
}

nlohmann::json VrcRenderer::describe() const {
    const double mb = 1024.0 * 1024.0;
    nlohmann::json d = {
        {"technique", "voxel_raycast"},
        {"transparency", m_transparent ? "front_to_back_along_ray" : "opaque"},
        {"grid", {m_size.x, m_size.y, m_size.z}},
        {"voxel_size", m_voxelSize},
        // Above 1 tubes are cut one voxel out of their axis' voxels (docs/scene-spec.md, vrc.neighbors).
        {"max_radius_voxels", m_voxelSize > 0 ? m_maxRadius / m_voxelSize : 0.0f},
        {"quantization", m_quantization},
        {"neighbors", m_spec.neighbors},
        {"opacity_threshold", m_spec.opacityThreshold},
        {"path_length_opacity", m_transparent && m_spec.pathLengthOpacity},
        {"pieces", m_pieces},
        {"copies", m_copies},
        {"copies_did_not_fit", m_copiesDidNotFit},
        {"piece_blocks", m_pieceBlockCount},
        {"piece_texture", m_pieceTexture.id() != 0},
        {"segments", m_segments},
        {"bytes_per_piece", m_bytesPerPiece},
        {"header_bytes", m_headerBytes},
        {"model_bytes", m_modelBytes},
        {"model_mb", double(m_modelBytes) / mb},
        {"encoding", m_paper ? "paper" : "compact16"},
        {"encoding_requested", m_spec.encoding == VrcSpec::Encoding::Paper ? "paper" : "compact16"},
        {"encoding_fallback",
         m_encodingFallback.empty() ? nlohmann::json(nullptr) : nlohmann::json(m_encodingFallback)},
        {"raw_lines_mb", double(m_rawBytes) / mb},
        {"build_ms", m_buildMs},
        {"build", m_gpuBuild ? "gpu" : "cpu"},
        {"upload_ms", m_uploadMs},
        {"lod", m_lodAtlas.id() != 0 ? lodDescription() : nlohmann::json(false)},
        {"soft_shadows", m_spec.shadows && m_spec.shadowMode == VrcSpec::ShadowMode::Soft},
        {"shadow_mode", !m_spec.shadows                                         ? "none"
                        : m_spec.shadowMode == VrcSpec::ShadowMode::Soft        ? "soft"
                        : m_spec.shadowMode == VrcSpec::ShadowMode::Hard        ? "hard"
                        : m_spec.shadowMode == VrcSpec::ShadowMode::DensityCone ? "density_cone"
                                                                                : "hard_tubes"},
        {"ao_method", !m_aoEnabled                                           ? "none"
                      : m_spec.ao.method == VrcSpec::Ao::Method::DensityRays ? "density_rays"
                      : m_spec.ao.method == VrcSpec::Ao::Method::Precomputed ? "precomputed"
                                                                             : "cone_traced"},
        {"ao_precompute_ms", m_aoPrecomputeMs},
        {"hard_shadows", m_shadowLines.id() != 0
                             ? nlohmann::json{{"level", m_shadowLevel},
                                              {"grid", {m_shadowGridSize.x, m_shadowGridSize.y, m_shadowGridSize.z}},
                                              {"build_ms", m_representativeMs}}
                             : nlohmann::json(false)},
        {"ambient_occlusion", m_ao && m_aoEnabled && m_spec.ao.method == VrcSpec::Ao::Method::ConeTraced
                                  ? m_ao->describe()
                                  : nlohmann::json(m_aoEnabled)}};
    if (m_halo) {
        // The ring must fit one voxel as the tubes (docs/scene-spec.md, style.halo).
        const float ringVoxels = m_voxelSize > 0 ? m_maxRadius * (1.0f + m_halo->geometry.width) / m_voxelSize : 0.0f;
        d["halo"] = {{"width", m_halo->geometry.width},
                     {"depth", m_halo->geometry.depth},
                     {"max_ring_radius_voxels", ringVoxels}};
    } else {
        d["halo"] = false;
    }
    if (m_paper)
        d["paper_encoding"] = {{"bits_per_piece", m_paperLayout.bitsPerPiece()},
                               {"end_bits", m_paperLayout.endBits},
                               {"interior_lattice", m_paperLayout.interiorLattice},
                               {"home_offset_bits", m_paperLayout.copies ? kPaperOffsetBits : 0},
                               // 5 as the paper, wider when a voxel holds more than 32 polylines.
                               {"local_line_bits", m_paperLayout.lineBits},
                               {"header_count_bytes", m_paperLayout.countBytes},
                               {"radius", m_paperLayout.radiusVaries ? "two unorm8 per piece" : "one for the model"},
                               {"palette_colors", m_paletteColors},
                               {"palette_exact", m_paletteExact},
                               // Largest colour channel error of the palette, in units of 1/255.
                               {"palette_max_error", m_paletteMaxError},
                               {"piece_bytes", m_pieces * m_bytesPerPiece},
                               // Beside the encoding, only with the id output: the pieces' global polyline ids.
                               {"global_id_bytes", m_globalIdBytes},
                               {"pack_ms", m_packMs}};
    return d;
}

TechniqueDescriptor voxelRaycastTechnique() {
    TechniqueDescriptor d;
    d.name = "voxel_raycast";
    d.summary =
        "rays through a voxel model of the lines (quantized pieces per voxel); opaque, or transparent "
        "composited front to back along each ray";
    d.paper = "Kanzler, Rautenhaus & Westermann 2019";
    d.backend = TechniqueBackend::Gl;
    d.data = {DataKind::Lines};
    // Chosen explicitly only: on the densest sets it beats the k-buffer, on small ones it loses
    // (docs/performance.md).
    d.autoData = {};
    // Every transparent mode name means the same here: front-to-back compositing along the ray.
    d.transparency = {Transparency::Opaque, Transparency::ObjectOrder, Transparency::KBuffer,
                      Transparency::DepthPeeling};
    d.transparencyAliases = {Transparency::ObjectOrder, Transparency::KBuffer};
    d.exactTransparency = Transparency::DepthPeeling;
    d.ao = {AoSpec::Method::ConeTraced};
    // Halos on the tubes the ray caster intersects (shaders/vrc_raycast.comp, vrcHaloHit).
    d.halo = {Transparency::ObjectOrder, Transparency::KBuffer, Transparency::DepthPeeling};
    d.pixelBuffers = [](const Scene& scene, DataKind) { return VrcRenderer::pixelBuffers(scene); };
    d.create = [](const Scene& scene, const TechniqueData& data, const TechniqueHooks&) -> std::unique_ptr<Technique> {
        // Region clipping is not implemented for the voxel model's ray marching (its per-voxel
        // line lists would need the entry-point rule of core/region.h at every sample).
        if (!data.region.unbounded()) refuseRegion(scene, "render.technique", "voxel_raycast");
        return VrcRenderer::create(scene, *data.lines);
    };
    return d;
}

}  // namespace tc::gl
