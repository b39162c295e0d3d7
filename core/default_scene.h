#pragma once
// The scene a dataset gets when it is given alone (`tubecast render DATASET`, `tubecast scene
// DATASET`): the conventions of the data's field, so the first picture is a sensible one
// (docs/scene-spec.md "A dataset alone"):
// - the camera fitted to the data (camera.fit, the scene default);
// - lines: radius 0.2 % of the bounding-box diagonal of the vertices; colour direction-encoded
//   for tractography (.trk, .tck: |dx|, |dy|, |dz| as RGB, as MRtrix, TrackVis and DIPY show
//   tracts), else the first scalar attribute through viridis, else the default constant;
// - particles: the radii and colours the file carries or implies (element radii and colours)
//   where it has them, else radius 0.5 x the mean spacing of a uniform cloud of that many
//   particles over the bounding box (spheres about touching) and the first scalar attribute
//   through viridis; a time series animates its data frames with a still camera;
// - opaque (the opacity default 1: `--set style.opacity=0.3` makes it transparent);
// - technique and transparency "auto".
#include <nlohmann/json.hpp>
#include <string>

#include "core/line_set.h"
#include "core/particle_set.h"

namespace tc {

// The radius rule for lines (a fraction of the bounding-box diagonal of the vertices).
constexpr float kDefaultLineRadiusFraction = 0.002f;

// `path`: the dataset file as the user gave it (written as dataset.path); exactly one of `lines`
// and `particles` is the dataset read from it.
nlohmann::json defaultSceneFor(const std::string& path, const LineSet* lines, const ParticleData* particles);

}  // namespace tc
