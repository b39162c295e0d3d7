#include "core/sort_keys.h"

#include <bit>
#include <cmath>

namespace tc {

// Bit-exactness with shaders/sort_keys.glsl: every operation below is an IEEE single-precision
// add, multiply, divide or sqrt, each correctly rounded on x86-64 SSE and in llvmpipe, written in
// the same order as the GLSL. The shader marks its results `precise` so Mesa does not fuse a
// multiply and an add into an FMA (which rounds once instead of twice); this file is compiled
// without FMA (x86-64 baseline, and the dot products are spelled out so -ffp-contract cannot
// matter for the order). glm::dot/length are avoided for the same reason.
namespace {
float dot3(const glm::vec3& a, const glm::vec3& b) {
    float xy = a.x * b.x + a.y * b.y;
    return xy + a.z * b.z;
}
}  // namespace

std::uint32_t sortKeyFromFloat(float value) {
    return sortKeyFromFloat(std::bit_cast<std::uint32_t>(value));
}

float floatFromSortKey(std::uint32_t key) {
    std::uint32_t bits = (key & 0x80000000u) ? (key & 0x7FFFFFFFu) : ~key;
    return std::bit_cast<float>(bits);
}

float segmentDistance(const glm::vec3& eye, const glm::vec3& x0, const glm::vec3& x1) {
    glm::vec3 d = x1 - x0;
    glm::vec3 e = eye - x0;
    float dd = dot3(d, d);
    float t = 0.0f;
    if (dd > 0.0f) t = std::fmin(std::fmax(dot3(e, d) / dd, 0.0f), 1.0f);
    glm::vec3 closest = e - t * d;  // eye - (x0 + t d), relative to x0 to keep precision
    return std::sqrt(dot3(closest, closest));
}

float segmentDepth(const glm::vec3& eye, const glm::vec3& forward, const glm::vec3& x0, const glm::vec3& x1) {
    return std::fmin(dot3(x0 - eye, forward), dot3(x1 - eye, forward));
}

std::uint32_t segmentSortKey(const glm::vec3& eye, bool orthographic, const glm::vec3& forward, const glm::vec3& x0,
                             const glm::vec3& x1) {
    return sortKeyFromFloat(orthographic ? segmentDepth(eye, forward, x0, x1) : segmentDistance(eye, x0, x1));
}

}  // namespace tc
