#include "cli/icet_compositor.h"

#include <IceT.h>
#include <IceTMPI.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

namespace tc::cli {

namespace {

// Exponent bias between a view depth and its key: 63 binades (see depthKey in the header).
constexpr std::uint32_t kKeyShift = 63u << 23;
constexpr float kMinDepth = 0x1p-63f;
constexpr float kMaxDepth = 0x1p63f;
constexpr float kMinKey = 0x1p-126f;  // the smallest normal float: keys stay clear of denormals,
                                      // which a flush-to-zero build of IceT would compare as 0

const char* icetErrorName(IceTEnum e) {
    switch (e) {
        case ICET_SANITY_CHECK_FAIL:
            return "ICET_SANITY_CHECK_FAIL";
        case ICET_INVALID_ENUM:
            return "ICET_INVALID_ENUM";
        case ICET_BAD_CAST:
            return "ICET_BAD_CAST";
        case ICET_OUT_OF_MEMORY:
            return "ICET_OUT_OF_MEMORY";
        case ICET_INVALID_OPERATION:
            return "ICET_INVALID_OPERATION";
        case ICET_INVALID_VALUE:
            return "ICET_INVALID_VALUE";
        default:
            return "unknown IceT error";
    }
}

// One icetCompositeImage call over the whole image (no valid-pixel viewport, no projection: the
// images are final), its errors as exceptions and its counters added to `stats`.
IceTImage runPass(const void* color, const float* depth, CompositeStats& stats) {
    const float black[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    IceTImage result = icetCompositeImage(color, depth, nullptr, nullptr, nullptr, black);
    if (IceTEnum e = icetGetError(); e != ICET_NO_ERROR) {
        throw Error(ExitCode::Internal, std::string("IceT compositing failed: ") + icetErrorName(e));
    }
    IceTDouble compositeSeconds = 0, totalSeconds = 0;
    IceTInt bytes = 0;
    icetGetDoublev(ICET_COMPOSITE_TIME, &compositeSeconds);
    icetGetDoublev(ICET_TOTAL_DRAW_TIME, &totalSeconds);
    icetGetIntegerv(ICET_BYTES_SENT, &bytes);
    stats.passes += 1;
    stats.icetCompositeMs += 1000.0 * compositeSeconds;
    stats.icetTotalMs += 1000.0 * totalSeconds;
    stats.bytesSent += std::uint64_t(bytes);
    return result;
}

}  // namespace

float depthKey(float viewDepth) {
    if (!(viewDepth < std::numeric_limits<float>::infinity())) return 1.0f;  // +inf, NaN: background
    if (viewDepth < kMinDepth) return kMinKey;
    if (viewDepth >= kMaxDepth) return std::nextafter(1.0f, 0.0f);
    return std::bit_cast<float>(std::bit_cast<std::uint32_t>(viewDepth) - kKeyShift);
}

float viewDepthOfKey(float key) {
    if (!(key < 1.0f)) return std::numeric_limits<float>::infinity();
    if (key < kMinKey) return kMinDepth;
    return std::bit_cast<float>(std::bit_cast<std::uint32_t>(key) + kKeyShift);
}

IcetCompositor::IcetCompositor(const MpiSession& mpi, int width, int height)
    : m_mpi(mpi), m_width(width), m_height(height) {
    TC_CHECK(width > 0 && height > 0);
    m_communicator = icetCreateMPICommunicator(mpi.comm());
    m_context = icetCreateContext(m_communicator);
    // IceT prints its errors (with the rank) to stdout; warnings would mix into tubecast's output.
    icetDiagnostics(ICET_DIAG_ERRORS | ICET_DIAG_ALL_NODES);
    icetResetTiles();
    icetAddTile(0, 0, width, height, 0);
    icetStrategy(ICET_STRATEGY_SEQUENTIAL);
    icetSingleImageStrategy(ICET_SINGLE_IMAGE_STRATEGY_AUTOMATIC);
    // tubecast composites the background itself afterwards (core/compositing.h).
    icetDisable(ICET_CORRECT_COLORED_BACKGROUND);
    if (IceTEnum e = icetGetError(); e != ICET_NO_ERROR) {
        throw Error(ExitCode::Internal, std::string("IceT setup failed: ") + icetErrorName(e));
    }
}

IcetCompositor::~IcetCompositor() {
    icetDestroyContext(m_context);
    icetDestroyMPICommunicator(m_communicator);
}

void IcetCompositor::checkAgreement(const FrameImages& images, CompositeMode mode, std::span<const int> order) const {
    const std::size_t n = std::size_t(m_width) * std::size_t(m_height);
    const int size = m_mpi.size();
    bool ok = images.width == m_width && images.height == m_height && images.rgba.size() == 4 * n &&
              images.depth.size() == n && images.normal.size() == 3 * n && images.id.size() == n &&
              (images.ao.empty() || images.ao.size() == n);
    // The order must be a permutation of the ranks, and the same on every rank (compared by a
    // hash: a mismatch would make IceT's ranks pair up differently and wait for each other).
    int orderHash = 0;
    if (!order.empty()) {
        std::vector<char> seen(std::size_t(size), 0);
        ok = ok && order.size() == std::size_t(size);
        for (std::size_t i = 0; ok && i < order.size(); ++i) {
            int r = order[i];
            ok = r >= 0 && r < size && !seen[std::size_t(r)];
            if (ok) seen[std::size_t(r)] = 1;
            orderHash = int((std::int64_t(orderHash) * 31 + r + 1) % 2147483647);
        }
    }
    const int hasAo = images.ao.empty() ? 0 : 1;
    // Minimum over ranks of each value and of its negation: min and max in one MPI_Allreduce.
    int v[7] = {ok ? 1 : 0, hasAo, -hasAo, int(mode), -int(mode), orderHash, -orderHash};
    MPI_Allreduce(MPI_IN_PLACE, v, 7, MPI_INT, MPI_MIN, m_mpi.comm());
    if (v[0] == 0) {
        throw Error(ExitCode::Internal, "composite: a rank passed images that are not " + std::to_string(m_width) +
                                            "x" + std::to_string(m_height) +
                                            " with every buffer, or an order that is not a permutation of the " +
                                            std::to_string(size) + " ranks");
    }
    if (v[1] != -v[2]) throw Error(ExitCode::Internal, "composite: some ranks have ambient occlusion, others not");
    if (v[3] != -v[4]) throw Error(ExitCode::Internal, "composite: the ranks passed different modes");
    if (v[5] != -v[6]) throw Error(ExitCode::Internal, "composite: the ranks passed different orders");
}

void IcetCompositor::composite(FrameImages& images, CompositeMode mode, std::span<const int> frontToBack,
                               StageSink& sink) {
    checkAgreement(images, mode, frontToBack);
    sink.begin("composite");
    icetSetContext(m_context);
    m_stats = {};
    const std::size_t n = images.pixelCount();
    const bool root = m_mpi.isRoot();

    std::vector<IceTInt> order(static_cast<std::size_t>(m_mpi.size()));
    if (frontToBack.empty()) {
        std::iota(order.begin(), order.end(), 0);
    } else {
        std::copy(frontToBack.begin(), frontToBack.end(), order.begin());
    }
    // Ordered in every pass, Z-buffer ones too: then all passes pair the images alike and ties
    // in depth go to the same rank in each (the header says why that matters).
    icetEnable(ICET_ORDERED_COMPOSITE);
    icetCompositeOrder(order.data());

    m_keys.resize(n);
    for (std::size_t i = 0; i < n; ++i) m_keys[i] = depthKey(images.depth[i]);

    // Pass "colour". IceT returns the composited image in buffers of its own, valid until its
    // next composite: each pass's result is copied out before the next pass.
    if (mode == CompositeMode::Opaque) {
        icetCompositeMode(ICET_COMPOSITE_MODE_Z_BUFFER);
        icetSetDepthFormat(ICET_IMAGE_DEPTH_FLOAT);
        icetDisable(ICET_COMPOSITE_ONE_BUFFER);  // the composited depth is wanted too
    } else {
        icetCompositeMode(ICET_COMPOSITE_MODE_BLEND);
        icetSetDepthFormat(ICET_IMAGE_DEPTH_NONE);
    }
    icetSetColorFormat(ICET_IMAGE_COLOR_RGBA_FLOAT);
    IceTImage result = runPass(images.rgba.data(), mode == CompositeMode::Opaque ? m_keys.data() : nullptr, m_stats);
    if (root) {
        const float* color = icetImageGetColorcf(result);
        if (mode == CompositeMode::Opaque) {
            const float* keys = icetImageGetDepthcf(result);
            m_resultKeys.assign(keys, keys + n);
            for (std::size_t i = 0; i < n; ++i) {
                if (m_resultKeys[i] < 1.0f) std::memcpy(&images.rgba[4 * i], &color[4 * i], 4 * sizeof(float));
            }
        } else {
            std::memcpy(images.rgba.data(), color, 4 * n * sizeof(float));
        }
    }

    // Pass "aov": normal and id of the nearest surface.
    m_aov.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
        std::memcpy(&m_aov[4 * i], &images.normal[3 * i], 3 * sizeof(float));
        std::memcpy(&m_aov[4 * i + 3], &images.id[i], sizeof(float));
    }
    icetCompositeMode(ICET_COMPOSITE_MODE_Z_BUFFER);
    icetSetColorFormat(ICET_IMAGE_COLOR_RGBA_FLOAT);
    icetSetDepthFormat(ICET_IMAGE_DEPTH_FLOAT);
    if (mode == CompositeMode::Opaque) {
        icetEnable(ICET_COMPOSITE_ONE_BUFFER);  // the depth is known from the colour pass
    } else {
        icetDisable(ICET_COMPOSITE_ONE_BUFFER);
    }
    result = runPass(m_aov.data(), m_keys.data(), m_stats);
    if (root) {
        if (mode == CompositeMode::Transparent) {
            const float* keys = icetImageGetDepthcf(result);
            m_resultKeys.assign(keys, keys + n);
        }
        const float* aov = icetImageGetColorcf(result);
        for (std::size_t i = 0; i < n; ++i) {
            if (!(m_resultKeys[i] < 1.0f)) continue;
            std::memcpy(&images.normal[3 * i], &aov[4 * i], 3 * sizeof(float));
            std::memcpy(&images.id[i], &aov[4 * i + 3], sizeof(float));
            images.depth[i] = viewDepthOfKey(m_resultKeys[i]);
        }
    }

    // Pass "ao": the float's 32 bits as one RGBA ubyte pixel, which IceT's Z-buffer mode moves
    // as a 32-bit word.
    if (!images.ao.empty()) {
        icetSetColorFormat(ICET_IMAGE_COLOR_RGBA_UBYTE);
        icetEnable(ICET_COMPOSITE_ONE_BUFFER);
        result = runPass(images.ao.data(), m_keys.data(), m_stats);
        if (root) {
            const IceTUInt* ao = icetImageGetColorcui(result);
            for (std::size_t i = 0; i < n; ++i) {
                if (m_resultKeys[i] < 1.0f) std::memcpy(&images.ao[i], &ao[i], sizeof(float));
            }
        }
    }
    sink.setItems(n);
    sink.end();
}

}  // namespace tc::cli
