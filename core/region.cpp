#include "core/region.h"

#include <algorithm>

namespace tc {

RayInterval rayInterval(const Ray& ray, const RegionBox& box) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    RayInterval r{-kInf, kInf};
    for (int k = 0; k < 3; ++k) {
        const float o = ray.origin[k], d = ray.dir[k];
        if (d == 0.0f) {
            // Parallel to the slab: inside for every t or for none ((lo - o) / 0 would give NaN
            // for an origin on the face).
            if (!(o >= box.lo[k] && o <= box.hi[k])) return {kInf, -kInf};
            continue;
        }
        const float inv = 1.0f / d;
        float a = (box.lo[k] - o) * inv, b = (box.hi[k] - o) * inv;
        if (a > b) std::swap(a, b);
        r.t0 = std::max(r.t0, a);
        r.t1 = std::min(r.t1, b);
    }
    return r;
}

}  // namespace tc
