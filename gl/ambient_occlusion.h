#pragma once
// Line ambient occlusion for the rasterized techniques (Groß & Gumhold 2020, Sect. 5.3): the
// density volume is voxelized on the CPU once per dataset (core/voxel_density.h), uploaded with a
// mip pyramid (gl/density_volume.h) and cone traced per shaded point (shaders/cone_tracing.glsl).
// Programs that trace cones are compiled with the define AMBIENT_OCCLUSION.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/region.h"
#include "core/scene.h"
#include "core/styled_lines.h"
#include "gl/ao_line_cache.h"
#include "gl/density_volume.h"

namespace tc::gl {

class AmbientOcclusion {
public:
    // Voxelizes `lines` at spec.resolution and uploads the volume. Needs a current context.
    // `region` (data-parallel rendering): the grid and cone length come from its data bounds, and
    // with its reduceDensity the volume holds every rank's density (core/voxel_density.h
    // buildLineDensity).
    static AmbientOcclusion create(const AoSpec& spec, const StyledLines& lines, const RegionSetup& region = {});

    // Binds the volume and sets the cone tracing uniforms of `program` (uAoCones, uAoAperture,
    // uAoDistance, uAoStrength, uAoStartOffset and the density uniforms).
    // With the line cache built, also binds it (gl/ao_line_cache.h).
    void apply(GLuint program) const;
    // The rasterized line renderers: builds the per-segment AO cache when spec.cache asks for it
    // (once per dataset; `geometry` holds `lines`). Then lineDefines() selects it in the shaders.
    void buildLineCache(const LineGeometry& geometry, const StyledLines& lines);
    // Defines of programs shading lines with lineAmbientOcclusion (shaders/ambient_occlusion.glsl).
    std::vector<std::string> lineDefines() const;
    nlohmann::json describe() const;

private:
    AoSpec m_spec;
    DensityVolume m_volume;
    float m_distance = 0;     // world units
    float m_startOffset = 0;  // world units: one voxel (see create)
    double m_voxelizeMs = 0, m_uploadMs = 0;
    std::size_t m_clampedSegments = 0;
    std::optional<AoLineCache> m_lineCache;
};

}  // namespace tc::gl
