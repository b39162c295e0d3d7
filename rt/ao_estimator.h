#pragma once
// Ambient occlusion at a shaded point for the ray tracer: the two render.ao.method variants
// (rt/cone_traced_ao.h, rt/ray_traced_ao.h) behind one interface.
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/region.h"
#include "core/scene.h"
#include "core/styled_lines.h"

namespace tc::rt {

class EmbreeLines;

class AoEstimator {
public:
    virtual ~AoEstimator() = default;
    // 1 = unoccluded, 0 = fully occluded, at world point p with unit normal n facing the viewer.
    // `pixel` seeds per-pixel sampling (deterministic: same pixel, same result); `segment` is the
    // shaded segment (cone tracing excludes its own tube). Thread-safe.
    virtual float visibility(const glm::vec3& p, const glm::vec3& n, std::uint32_t pixel,
                             std::uint32_t segment) const = 0;
    virtual nlohmann::json describe() const = 0;
};

// By spec.method. `embree` must outlive the estimator (ray_traced traces against it). `region`:
// data bounds and density reduction of data-parallel rendering, for "cone_traced" (the caller
// refuses "ray_traced" with a region: its rays would see only this rank's data).
std::unique_ptr<AoEstimator> makeAoEstimator(const AoSpec& spec, const StyledLines& lines, const EmbreeLines& embree,
                                             const RegionSetup& region = {});

}  // namespace tc::rt
