#pragma once
// Sort-last compositing of one frame's FrameImages across the ranks of an MpiSession with IceT
// (icetCompositeImage on images the ranks already rendered; IceT's OpenGL layer is not used).
// Rank 0 receives the composited FrameImages, the image one process would have rendered:
//
//   Opaque       IceT's Z-buffer mode: per pixel, every buffer (rgba, depth, normal, id, ao) of the
//                rank whose depth is smallest.
//   Transparent  IceT's ordered blending of the premultiplied rgba, front to back in the order the
//                caller gives (the k-d regions' view order): IceT's operator is premultiplied
//                "over", back * (1 - front.a) + front, the same as tubecast's front-to-back
//                "under" (C += (1 - A) C_layer, A += (1 - A) A_layer); depth, normal, id and ao
//                are the first surface's, taken by the Z-buffer mode as for opaque frames.
//
// IceT composites colour and depth only. The AOVs ride as colour in further Z-buffer passes over
// the same depth, so every pass picks the same rank per pixel and the values arrive bit for bit:
//   pass "colour"  RGBA float = rgba           (Z-buffer or blend)
//   pass "aov"     RGBA float = normal xyz, id's 32 bits stored in the fourth float
//   pass "ao"      RGBA ubyte = ao's 32 bits   (only when the images carry ao)
// IceT's depth must lie in [0, 1) (1 = background; a pixel is "active" only if its depth < 1), so
// the view depth is mapped by depthKey below: exact and order-preserving for view depths in
// [2^-63, 2^63), the composited view depth is recovered exactly. Background pixels (+inf on every
// rank) keep rank 0's own values, which are every rank's background values.
//
// Ties (equal depth on two ranks) go to the same rank in every pass, because every pass runs with
// IceT's ordered compositing in the same order, so IceT pairs the images identically; which of
// the tied ranks wins is IceT's choice.
//
// Strategy: one tile covering the whole image, ICET_STRATEGY_SEQUENTIAL: IceT's manual recommends
// it for a single tile (REDUCE first redistributes tiles, which only helps with several; VTREE and
// SPLIT cannot composite in order), with the single-image strategy left to IceT (automatic:
// radix-k, binary swap, or tree by the number of ranks).
#include <cstdint>
#include <span>
#include <vector>

#include "cli/mpi_session.h"
#include "core/frame_images.h"
#include "core/stage_sink.h"

struct IceTContextStruct;
struct IceTCommunicatorStruct;

namespace tc::cli {

enum class CompositeMode {
    Opaque,       // nearest surface wins (Z-buffer)
    Transparent,  // premultiplied layers blended front to back in the given order
};

// IceT's depth for a view depth: the float whose bits are d's less 63 binades of exponent, so
// that d in [2^-63, 2^63) maps to [2^-126, 1) preserving order and bits; smaller depths (and
// 0 or negative) map to 2^-126, larger finite ones just below 1, +inf and NaN to 1 (background).
float depthKey(float viewDepth);
// The inverse on [2^-126, 1); 1 (and above) gives +inf.
float viewDepthOfKey(float key);

// What the last composite cost (IceT's own counters, summed over its passes).
struct CompositeStats {
    int passes = 0;
    double icetCompositeMs = 0;   // ICET_COMPOSITE_TIME: compositing work on this rank
    double icetTotalMs = 0;       // ICET_TOTAL_DRAW_TIME: the icetCompositeImage calls
    std::uint64_t bytesSent = 0;  // ICET_BYTES_SENT by this rank
};

class IcetCompositor {
public:
    // Collective. An IceT context on a duplicate of mpi.comm() for width x height frames,
    // displayed on rank 0. `mpi` must outlive the compositor.
    IcetCompositor(const MpiSession& mpi, int width, int height);
    ~IcetCompositor();
    IcetCompositor(const IcetCompositor&) = delete;
    IcetCompositor& operator=(const IcetCompositor&) = delete;

    // Collective. Composites every rank's `images` (width x height, all buffers allocated; ao
    // either on every rank or on none) into rank 0's `images`; the other ranks' images are left
    // as they were. `frontToBack` lists every rank once, nearest region first; the same on every
    // rank. Transparent frames need it; opaque ones use it only to break depth ties consistently
    // and may pass it empty (rank order). The time goes to `sink` as the stage "composite" (items:
    // pixels). Throws Error(Internal) on every rank if the ranks disagree on mode or ao or a
    // rank's images have the wrong size, and on an IceT error.
    void composite(FrameImages& images, CompositeMode mode, std::span<const int> frontToBack, StageSink& sink);

    const CompositeStats& lastStats() const { return m_stats; }
    int width() const { return m_width; }
    int height() const { return m_height; }

private:
    void checkAgreement(const FrameImages& images, CompositeMode mode, std::span<const int> order) const;

    const MpiSession& m_mpi;
    int m_width;
    int m_height;
    IceTCommunicatorStruct* m_communicator = nullptr;
    IceTContextStruct* m_context = nullptr;
    CompositeStats m_stats;
    // Scratch reused across frames: the depth keys, the packed normal + id, and rank 0's copies of
    // the passes' results.
    std::vector<float> m_keys;
    std::vector<float> m_aov;
    std::vector<float> m_resultKeys;
};

}  // namespace tc::cli
