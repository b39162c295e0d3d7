#pragma once
// Camera per frame: fitting to the data, orbits and keyframe paths.
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/line_set.h"
#include "core/scene.h"

namespace tc {

// The scene's camera with "fit" applied: target at the centre of `bounds`, eye along the given
// view direction at the distance where the bounding sphere fills the smaller field of view.
Camera fitCamera(const CameraSpec& spec, const Bounds& bounds, float aspect);

// Camera of animation frame `frame` (0-based), starting from the (fitted) base camera.
// Orbit: eye and up rotated by frame * degrees / frames about the axis through the target.
// Keyframes: Catmull-Rom through the keys' eye, target and up; held before the first and after
// the last key.
Camera cameraAtFrame(const AnimationSpec& animation, const Camera& base, int frame);

// --frames syntax (Blender style, inclusive): "0..99", "0..99:5", "3,7,12..20"; empty = all.
// Frames outside [0, frameCount) are errors; duplicates are removed, order is ascending.
std::vector<int> parseFrameList(const std::string& spec, int frameCount);

}  // namespace tc
