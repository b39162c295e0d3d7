#pragma once
// Visibility-sort keys (Groß & Gumhold 2020, Sect. 4.1): a float per segment, mapped to a uint32
// whose unsigned order is the float order, so a radix sort over the uint32 sorts front to back.
// shaders/sort_keys.glsl is the GLSL twin of every function here; both compute the same
// operations in the same order so the GPU key equals this one bit for bit (see sort_keys.cpp).
#include <cstdint>
#include <glm/glm.hpp>

namespace tc {

// Order-preserving float -> uint32 ("float flip"): for a < b (IEEE total order on non-NaN
// values, with -0 < +0) sortKeyFromFloat(a) < sortKeyFromFloat(b). Non-negative floats get their
// bits with the top bit set, negative floats their bits inverted, so negative keys (power
// distances of particles) sort before all non-negative ones. +NaN sorts after +inf, -NaN before
// -inf.
constexpr std::uint32_t sortKeyFromFloat(std::uint32_t floatBits) {
    return (floatBits & 0x80000000u) ? ~floatBits : (floatBits | 0x80000000u);
}
std::uint32_t sortKeyFromFloat(float value);

// Inverse of sortKeyFromFloat: floatFromSortKey(sortKeyFromFloat(x)) has the bits of x.
float floatFromSortKey(std::uint32_t key);

// Minimum Euclidean distance from `eye` to the segment [x0, x1] (the closest point is clamped to
// the segment; a degenerate segment x0 == x1 gives |eye - x0|). The perspective sort key.
float segmentDistance(const glm::vec3& eye, const glm::vec3& x0, const glm::vec3& x1);

// Minimum view depth dot(x - eye, forward) over the segment, i.e. over its two end points (the
// depth is linear along the segment). The orthographic sort key; `forward` is the unit view
// direction. Negative for points behind the eye plane.
float segmentDepth(const glm::vec3& eye, const glm::vec3& forward, const glm::vec3& x0, const glm::vec3& x1);

// The key the GPU key pass (gl/sort_keys.h) writes for segment [x0, x1]:
// sortKeyFromFloat(orthographic ? segmentDepth(...) : segmentDistance(...)).
std::uint32_t segmentSortKey(const glm::vec3& eye, bool orthographic, const glm::vec3& forward, const glm::vec3& x0,
                             const glm::vec3& x1);

}  // namespace tc
