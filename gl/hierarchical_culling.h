#pragma once
// Depth slices with hierarchical culling (Groß & Gumhold 2020, Sect. 4.3): the sorted segments
// are drawn as `slices` consecutive draw calls; after each, a mip pyramid of what is already
// hidden is rebuilt from the render target (shaders/cull_pyramid.comp), and the next slice tests
// every billboard where it is built and every fragment before its ray casting against it
// (shaders/hierarchical_culling.glsl; opaque fragments only where that pays, setFragmentTest).
// Opaque: max view depth; transparent: min accumulated opacity. Culled segments are counted with
// an atomic counter, read back once per frame.
// The transparent fragment test is a depth test: after each slice the pixels it hides get depth 0
// (shaders/cull_mark.frag), and the line shaders test depth before they run
// (early_fragment_tests). On llvmpipe that is the test that skips a shader: a 4x4 block whose
// pixels all fail it is not shaded, while a `discard` in the shader runs every lane through all of
// the code anyway (docs/performance.md, "Depth slices and culling").
#include <cstdint>
#include <string>
#include <vector>

#include "core/scene.h"
#include "core/stage_sink.h"
#include "gl/line_geometry.h"
#include "gl/objects.h"

namespace tc::gl {

class SegmentOrder;

class HierarchicalCulling {
public:
    enum class Target { MaxDepth, MinOpacity };

    // Compiles the pyramid programs and, for the compute billboard path, the culling billboard
    // program. Needs a current context.
    static HierarchicalCulling create(Target target, const CullingSpec& spec, const LineGeometry& geometry);

    // Per-pixel bytes of the pyramid (its levels: 4 B x (1/4 + 1/16 + ...) < 2 B a pixel).
    static constexpr std::size_t kBytesPerPixel = 2;
    // Per-pixel bytes of the depth attachment MinOpacity marks (16-bit depth).
    static constexpr std::size_t kMarkBytesPerPixel = 2;

    // Whether MaxDepth draws test each fragment against the pyramid before its ray casting
    // (CULL_FRAGMENT_TEST, a `discard`). Auto: where a discard skips the rest of the shader (GPUs),
    // not on software rasterizers (isSoftwareRasterizer): on llvmpipe every lane of a block runs the
    // whole shader anyway and the test only costs (5-11 % of the culled opaque draw's CPU time,
    // docs/performance.md). Either way the
    // image is the same: the test drops only fragments the depth test would reject. Applies to
    // the HierarchicalCulling objects created after the call; tests force On and Off.
    enum class FragmentTest { Auto, On, Off };
    static void setFragmentTest(FragmentTest mode);

    // Defines for draw programs that cull per billboard (vertex and geometry paths) and, for
    // MaxDepth with the fragment test, per fragment: DRAW_ORDER, CULLING, CULL_MAX_DEPTH |
    // CULL_MIN_OPACITY[, CULL_FRAGMENT_TEST].
    std::vector<std::string> drawDefines() const;

    // Draws all segments of `geometry` with `program` (compiled with drawDefines()) in slices of
    // the order `order`, rebuilding the pyramid from `source` (the depth texture for MaxDepth,
    // the accumulation target for MinOpacity) between slices. The caller has bound the target
    // framebuffer and set the program's other uniforms; the billboards of the compute path are
    // built here, per slice. MinOpacity: the framebuffer has a depth attachment, which this clears
    // and marks; the depth test is on during the draws and off again after them.
    void drawSliced(const LineGeometry& geometry, const SegmentOrder& order, GLuint program, const Texture& source,
                    const FrameSetup& setup);
    // Segments culled by the last drawSliced(), read back as stage "culling" of `timer` (its
    // items column). Waits for the draw to finish.
    std::uint64_t readCulled(StageSink& timer) const;

    int slices() const { return m_slices; }
    nlohmann::json describe() const;

    // The pyramid alone, for tests: (re)allocates it for width x height, builds it from `source`
    // (depth values are scaled by farDepth) and reads stored level `level` (pyramid level + 1) back (row 0 = GL's
    // bottom row).
    void build(const Texture& source, int width, int height, float farDepth);
    std::vector<float> readLevel(int level, glm::ivec2& size) const;

private:
    HierarchicalCulling() = default;
    void resize(int width, int height);
    void reset();
    void rebuild(const Texture& source, float farDepth);
    void setUniforms(GLuint program) const;
    void markHidden() const;  // MinOpacity, after a rebuild: cull_mark.frag

    Target m_target = Target::MaxDepth;
    int m_slices = 10;
    float m_threshold = 0.95f;
    bool m_fragmentTest = false;  // MaxDepth: CULL_FRAGMENT_TEST (setFragmentTest)
    Program m_fromSource, m_fromLevel, m_billboards;
    Program m_mark;  // MinOpacity: cull_mark.frag
    VertexArray m_emptyVao;
    Buffer m_pyramid;                      // all levels, row by row
    std::vector<glm::ivec2> m_levelSizes;  // index i = pyramid level i + 1
    std::vector<GLint> m_levelOffsets;     // in floats
    int m_width = 0, m_height = 0;
    Buffer m_counter;
};

}  // namespace tc::gl
