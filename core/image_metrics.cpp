#include "core/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace tc {

ImageMetrics compareRgba(const std::vector<float>& a, const std::vector<float>& b) {
    TC_CHECK_OP(a.size(), ==, b.size());
    ImageMetrics m;
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        double d = double(std::clamp(a[i], 0.0f, 1.0f)) - double(std::clamp(b[i], 0.0f, 1.0f));
        sum += d * d;
        m.maxError = std::max(m.maxError, std::abs(d));
    }
    m.rmse = a.empty() ? 0.0 : std::sqrt(sum / double(a.size()));
    m.psnr = m.rmse > 0 ? 20.0 * std::log10(1.0 / m.rmse) : std::numeric_limits<double>::infinity();
    return m;
}

}  // namespace tc
