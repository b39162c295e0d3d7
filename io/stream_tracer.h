#pragma once
// dataset.trace: streamlines traced through the vector field of a VTK grid with vtkStreamTracer
// (Runge-Kutta 4-5 with error control), turned into a LineSet.
#include <string>

#include "core/line_set.h"
#include "core/scene.h"

namespace tc {

// Reads the grid at `path` by extension: .vti (image data), .vtr (rectilinear), .vts
// (structured), .vtu (unstructured), .vtk (legacy, any data set type), .ex2/.exo/.e (Exodus II:
// every block's nodal variables at the first time step, blocks appended into one grid).
//
// - The vector is the point array spec.vector (3 components), or spec.components assembled
//   into one array called "velocity" (or "trace_vector" if the grid already has "velocity").
// - Seeds (spec.seeds of them): "random" uniform in the grid's bounding box (std::mt19937 with
//   spec.randomSeed; seeds outside cells trace nothing), "uniform" cell centres of a regular
//   lattice over the bounding box with about that many points (flat axes get one layer),
//   "line" evenly from spec.lineFrom to spec.lineTo inclusive.
// - Each seed traced "both" ways gives ONE polyline (the backward half reversed, then the
//   forward half), not VTK's two.
// - Step: spec.stepLength cell lengths initially, adapted between 1/20 and 2.5 times that
//   (ParaView's 0.01 .. 0.5 for the default 0.2); a line ends at the last step inside the grid;
//   max error 1e-6; at most spec.maxSteps steps and spec.maxLength arc length per direction
//   (0 = the bounding box diagonal).
// - Point attributes: every point array of the grid interpolated along the lines, plus VTK's
//   IntegrationTime, Vorticity, Rotation and AngularVelocity; vectors are split like the VTK
//   line reader does (name_x, name_y, name_z, name_magnitude), so "speed" derives from them.
// - The result is passed through cleanLineSet(); what it removed goes to `report`.
//
// Throws InputError "PATH: ..." naming the array ("dataset.trace.vector: no point array
// \"v\" (available: ...)") or VTK's first error.
LineSet traceStreamlines(const std::string& path, const TraceSpec& spec, CleanReport* report = nullptr);

// Whether the extension names a grid traceStreamlines reads (.vti, .vtr, .vts, .vtu, .vtk, Exodus).
bool isTraceableGridFile(const std::string& path);

}  // namespace tc
