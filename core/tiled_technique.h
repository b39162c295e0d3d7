#pragma once
// Tiles and anti-aliasing around any technique (core/tiling.h): renders the frame as the
// tiles of a TilePlan, each with `samples` jittered sub-pixel positions, by calling the wrapped
// technique's render() with a FrameSetup whose window is that tile and sample, and stitches the
// results into the full image. The wrapped technique is unchanged: its shaders turn the window
// into an exact off-axis sub-frustum (gl/view_window.h), and everything global about the view
// (segment sort, culling decisions, AO volume, sphere bounds) is computed from the full camera.
//
// Accumulation (a box filter over the pixel: the average of the samples, in float):
//   rgba (premultiplied) and ao: the average of the samples;
//   depth, normal, id: the sample nearest to the pixel centre (core/tiling.h nearestToCentre),
//   so they hold values of actual surfaces, never a blend.
#include <memory>

#include "core/technique.h"
#include "core/tiling.h"

namespace tc {

class TiledTechnique final : public Technique {
public:
    // `keep`: which first-surface AOVs the stitched image keeps; the others are left empty so a
    // huge frame holds one full-size copy of only what will be written. The wrapped technique
    // must give at least those.
    TiledTechnique(std::unique_ptr<Technique> inner, TilePlan plan, int samples, KeptAovs keep);

    // setup.width x height is the full image (the plan's); setup.window must be the full window.
    // Forwards to the wrapped technique (once per frame, not per tile).
    void prepareFrame(int frame, StageSink& sink) override { m_inner->prepareFrame(frame, sink); }
    void render(const FrameSetup& setup, FrameImages& out, StageSink& timer) override;
    nlohmann::json describe() const override;

private:
    std::unique_ptr<Technique> m_inner;
    TilePlan m_plan;
    std::vector<glm::vec2> m_offsets;
    std::size_t m_nearest = 0;  // the sample whose depth, normal and id are kept
    KeptAovs m_keep;
    FrameImages m_tile;  // one tile's result, reused
};

// `inner` itself when the plan has one tile and samples == 1 (the untiled path, bit for bit),
// else a TiledTechnique around it.
std::unique_ptr<Technique> wrapInTiles(std::unique_ptr<Technique> inner, const TilePlan& plan, int samples,
                                       KeptAovs keep);

}  // namespace tc
