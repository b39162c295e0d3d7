#pragma once
// Brute-force CPU references the GPU techniques are tested against, pixel by pixel. They use the
// same ray (core/camera.h), intersection (core/rounded_cone.h) and shading (core/shading.h) as the
// shaders, so differences are the GPU's float behaviour, not the method.
#include "core/camera.h"
#include "core/frame_images.h"
#include "core/scene.h"
#include "core/styled_lines.h"

namespace tc {

// Opaque rounded-cone tubes: every segment against every pixel-centre ray (row 0 = top). Per
// segment the visible t is tIn if > 0, else tOut if > 0 (an eye inside a tube sees its inner
// wall), else none; the nearest wins and ties keep the lower segment index (a GL depth test LESS
// in draw order). Writes depth (view space: t * dot(dir, forward); orthographic rays start on the
// eye plane, so t), outward world normal, the polyline id of the segment's first vertex, and
// premultiplied rgba with alpha 1: the per-vertex colour, linear along the segment by the hit's
// clamped projection parameter, shaded two-sided Blinn-Phong. Background: +inf depth, normal 0,
// kBackgroundId, rgba 0. Parallel over rows (oneTBB). O(pixels x segments): small scenes only.
FrameImages renderReferenceOpaque(const StyledLines& lines, const Camera& camera, const LightingSpec& light, int width,
                                  int height);

}  // namespace tc
