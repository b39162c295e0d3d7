#pragma once
// Small line scenes for the unit tests (CPU models) and the gl tests (GPU against CPU): hand-made
// polylines, and random bent polylines with per-vertex radii, built directly as StyledLines (the
// renderer's input) so a test controls every radius and colour. Deterministic across compilers:
// only std::mt19937's raw output is used (the standard fixes it; std::uniform_*_distribution is
// implementation-defined). No GL.
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/scene.h"
#include "core/styled_lines.h"

namespace tc::test {

struct TestVertex {
    glm::vec3 position;
    float radius;
    glm::vec4 color{0.8f, 0.5f, 0.2f, 1.0f};  // linear RGB, straight alpha
};
using TestPolyline = std::vector<TestVertex>;  // >= 2 vertices, no two consecutive ones equal

// StyledLines as styleLines() would build them: polyline p gets id p, consecutive vertices form
// the segments in order, first/last flags, bounds grown by radii and maxRadius.
StyledLines makeStyledLines(const std::vector<TestPolyline>& polylines);

struct RandomSceneOptions {
    int polylines = 4;
    int minSegments = 1, maxSegments = 10;  // per polyline, uniform
    float radiusMin = 0.02f;                // per-vertex radius = radiusMin * radiusRatio^u, u in [0,1)
    float radiusRatio = 10.0f;
    float stepMin = 0.15f, stepMax = 0.45f;  // segment length
    float maxBendDeg = 80.0f;                // angle between consecutive segment directions
    float extent = 0.8f;                     // start points uniform in [-extent, extent]^3
};

// Random bent polylines around the origin, random per-vertex colours; same seed, same scene.
StyledLines randomLineScene(std::uint32_t seed, const RandomSceneOptions& options = {});

// A perspective camera at `eye` looking at `target`, and its orthographic twin showing `height`
// world units vertically.
Camera lookAt(glm::vec3 eye, glm::vec3 target = {0, 0, 0}, glm::vec3 up = {0, 1, 0}, float fovYDeg = 40.0f);
Camera orthographic(glm::vec3 eye, glm::vec3 target, float height, glm::vec3 up = {0, 1, 0});

// A point on the sphere of radius `distance` around the origin, its direction from the seed
// (golden-angle spiral): an eye for views from every side.
glm::vec3 eyeFromSeed(std::uint32_t seed, float distance);

// A voxel_raycast scene of w x h pixels on a grid of `resolution` voxels; every other key default.
Scene vrcScene(int w, int h, int resolution, Transparency transparency);

}  // namespace tc::test
