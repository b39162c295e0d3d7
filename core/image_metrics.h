#pragma once
// Difference metrics between two frames' RGBA buffers, computed in memory (the frame loop compares
// each frame with its reference before anything is encoded). Same definitions as io's
// compareImages over files: RMSE over all RGBA values, PSNR = 20 log10(1 / RMSE) for signals in
// [0, 1], max absolute difference.
#include <cstddef>
#include <vector>

namespace tc {

struct ImageMetrics {
    double rmse = 0, psnr = 0, maxError = 0;
};

// Values are clamped to [0, 1] first (what an 8-bit or display image can show). Sizes must match.
ImageMetrics compareRgba(const std::vector<float>& a, const std::vector<float>& b);

}  // namespace tc
