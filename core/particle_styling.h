#pragma once
// Styling of particles with the same `style` mappings as lines (core/styling.h): radius, colour
// and opacity from attributes or constants.
#include <string>

#include "core/particle_set.h"
#include "core/scene.h"
#include "core/styled_lines.h"
#include "core/styled_particles.h"
#include "core/styling.h"

namespace tc {

// Radius: a style.radius attribute mapping if given, else the data's own radii (element radii,
// MMPLD radii) if it has them, else the constant style.radius. Colour likewise: a style.color
// mapping, else the data's colours (CPK, MMPLD), else the constant. Opacity always comes from
// style.opacity, times the data colour's alpha when the data has colours. Throws InputError
// naming `sceneFile` and the style key when an attribute is missing.
StyledParticles styleParticles(const ParticleSet& particles, const StyleSpec& style, const std::string& sceneFile);

// The range style.color's attribute is mapped over for these particles (core/styling.h
// colorMappingRange; an automatic range is this data frame's).
std::optional<ValueRange> colorMappingRange(const ParticleSet& particles, const StyleSpec& style,
                                            const std::string& sceneFile);

// Every vertex of a styled line set as a sphere of the vertex's radius and colour (the
// "spheres" technique drawing a line dataset); ids are polyline ids.
StyledParticles particlesFromLineVertices(const StyledLines& lines);

}  // namespace tc
