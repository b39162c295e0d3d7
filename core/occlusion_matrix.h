#pragma once
// The occlusion penalties h_ij of opacity optimization (Günther, Rössl & Theisel 2013, Algorithm 1)
// from per-pixel fragment lists: for each fragment A and each fragment B behind it in the same
// pixel, h(i, j) += 1 - frac(B.w) and h(i, j + 1) += frac(B.w), i = round(A.w), j = floor(B.w).
// Each column j is then divided by part j's fragment count (counted with the same weights), so
// h_ij in [0,1] is the fraction of part j's pixels that part i covers and q means the same at
// every image size. A part never occludes itself (i == target is skipped): a part's own fragments
// overlap at its joints, which says nothing about which line hides which. No OpenGL.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/opacity_optimization.h"

namespace tc {

// One fragment: view depth and the blending parameter w = part + frac, part = floor(w) (kept
// split, see OpacityParts).
struct LineFragmentW {
    float depth = 0;
    std::uint32_t part = 0;
    float frac = 0;  // in [0,1); 0 at the last part of a polyline
};

// Fragment lists of an image in compressed rows: pixel p owns fragments [offsets[p], offsets[p+1]).
struct FragmentLists {
    int width = 0;  // pixels per image row (0: unknown), for walking the image in tiles
    std::vector<std::uint64_t> offsets{0};
    std::vector<LineFragmentW> fragments;

    std::size_t pixelCount() const { return offsets.size() - 1; }
    // Sorts each pixel's list front to back (depth, then part, so equal depths are deterministic).
    void sortByDepth();
};

// The lists a render at `scale` of the width and height would sample (render.opacity.
// occlusion_scale): pixel (X, Y) of the small image, X < max(1, floor(width * scale)), takes the
// list of the full-size pixel that contains its centre, floor((X + 0.5) / scale) (same for Y).
// Rasterizing at the small size samples the same tubes at those centres (shifted by less than a
// full-size pixel), so this is that render without a second list pass. `lists.width` must be set;
// `height` is the full image's. Scale 1 returns a copy. Copies the fragments (sorted order kept).
FragmentLists subsampleLists(const FragmentLists& lists, int height, double scale);

// Part j's fragment count: sum over fragments of 1 - frac to floor(w) and frac to floor(w) + 1.
std::vector<double> partFragmentCounts(const FragmentLists& lists, std::size_t partCount);

// Algorithm 1 as written: one loop over pixels and pairs, accumulating into an ordered map. The
// reference the fast path is tested against. Lists must be sorted front to back. Without
// `clampToOne` the normalised sums are kept as they are (core/fragment_occlusion.h's matrix).
SparseMatrixD occlusionMatrixReference(const FragmentLists& lists, std::size_t partCount, bool clampToOne = true);

// The same sum, parallel over image tiles with oneTBB: each thread sums a tile's pairs in a dense
// matrix over the tile's parts and flushes them as (i, j, sum) records; a counting sort on i and
// a per-row merge build the compressed rows. The per-pixel work is quadratic in the list length
// by nature (every front part pairs with every part behind it, and H's per-pixel contribution
// has that many distinct entries), but repeated front parts are counted once with multiplicity.
// Each h_ij is summed and normalised in double and rounded to float once, straight into the form
// OpacityEnergy keeps (pass the result to it as an rvalue: its arrays are taken over, not copied).
SparseMatrixF occlusionMatrix(const FragmentLists& lists, std::size_t partCount);

// occlusionMatrix with its buffers kept from call to call, for the renderer's frames: fresh buffers
// (at 8k parts ~250 MB of pair records and their row-sorted copy, plus H's 26 MB) were ~100k page
// faults per frame, first-touched and zeroed by the kernel (`tubecast_fragment_occlusion_bench FILE
// --assembled 1` prints the minor page faults per call, with `--reuse 1` those of kept buffers).
// Holds that memory between calls until release() or destruction.
class OcclusionAssembler {
public:
    OcclusionAssembler();
    ~OcclusionAssembler();
    OcclusionAssembler(OcclusionAssembler&&) noexcept;
    OcclusionAssembler& operator=(OcclusionAssembler&&) noexcept;

    // H of `lists` into `h`, the same values as occlusionMatrix. h's own arrays are reused when
    // they hold enough non-zeros (hand the previous frame's H back in: OpacityEnergy::releaseOcclusion).
    void assemble(const FragmentLists& lists, std::size_t partCount, SparseMatrixF& h);
    // Frees the kept buffers.
    void release();

private:
    struct Buffers;
    std::unique_ptr<Buffers> m_buffers;
};

}  // namespace tc
