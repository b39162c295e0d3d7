#pragma once
// Per-vertex attributes derived from a line set's geometry, computed only when a style names
// them (core/styling.cpp asks for a name the dataset does not have). A dataset attribute of the
// same name always wins: readers and generators may already provide "arc_length" or "speed".
//
//   arc_length     distance along the polyline from its first vertex
//   line_length    total length of the vertex's polyline
//   curvature      1 / radius of the circle through the vertex and its two neighbours (Menger
//                  curvature, exact for samples of a circle); end vertices copy their neighbour,
//                  2-vertex polylines get 0
//   torsion        signed turning angle of the discrete binormal (p[i-1], p[i], p[i+1]) from one
//                  vertex to the next, divided by the segment length between them, averaged onto
//                  vertices; positive for right-handed helices (tau = c / (a^2 + c^2) for
//                  (a cos t, a sin t, c t)); 0 where the curve is locally straight
//   local_density  number of distinct polylines passing through the vertex's voxel, in a grid of
//                  kLocalDensityResolution cubic voxels along the longest axis of the bounds
//                  (segments are walked in quarter-voxel steps, so long segments count in every
//                  voxel they cross)
//   speed          |velocity|: of the vector the lines were traced along (LineSet::velocity),
//                  else from a "velocity_magnitude" attribute or from x/y/z components
//                  named velocity_*, vel_* or v_* (as the VTK readers split vectors)
#include <string>
#include <vector>

#include "core/line_set.h"

namespace tc {

inline constexpr int kLocalDensityResolution = 64;

const std::vector<std::string>& derivedAttributeNames();
bool isDerivedAttribute(const std::string& name);

// Computes one derived attribute (range updated). Throws InputError "<what is missing>" when it
// cannot be derived (speed without velocity components); the caller prefixes the location.
Attribute computeDerivedAttribute(const LineSet& lines, const std::string& name);

// Appends every name in `names` that is derived and missing from `lines`.
void addDerivedAttributes(LineSet& lines, const std::vector<std::string>& names);

}  // namespace tc
