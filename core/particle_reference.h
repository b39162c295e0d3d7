#pragma once
// CPU reference compositor for small particle scenes: per pixel, every sphere interval the
// pixel ray crosses (core/sphere_glyph.h), sorted exactly by entry distance, composited front to
// back with the same opacity and emission as the GPU (shaders/sphere_glyph.glsl). The ground
// truth of the sphere renderer's tests: exact for spheres that do not intersect each other.
#include <vector>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/scene.h"
#include "core/styled_particles.h"

namespace tc {

struct ParticleReferenceOptions {
    SpheresSpec spheres;
    LightingSpec lighting;
    bool opaque = false;  // first hit only, alpha 1 (render.transparency "opaque")
};

// Renders width x height (row 0 = top) with rays from tc::pixelRay. rgba is linear premultiplied;
// depth, normal and id describe the first sphere along each ray. No ambient occlusion (A_O = 1,
// L_A = 0). Cost O(pixels x spheres overlapping them): for tests.
FrameImages renderParticlesReference(const StyledParticles& particles, const Camera& camera, int width, int height,
                                     const ParticleReferenceOptions& options);

}  // namespace tc
