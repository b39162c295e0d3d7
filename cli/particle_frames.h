#pragma once
// The frame loop's side of particle datasets (M6): styles the data frame each animation frame
// shows (min(frame, last), or dataset.frame pinned) and hands it to the sphere renderer when it
// changes (per-frame upload, voxelization and sort, as in Staib et al. 2015's dynamic timings).
#include <memory>

#include "core/line_set.h"
#include "core/particle_set.h"
#include "core/scene.h"
#include "gl/technique.h"

namespace tc::gl {
class SphereRenderer;
class StageTimer;
}  // namespace tc::gl

namespace tc::rt {
class RaytracedParticles;
}  // namespace tc::rt

namespace tc::cli {

class ParticleFrames {
public:
    // Styles every frame's bounds up front (for the camera fit) but only the first shown frame's
    // particles. Throws InputError for style attributes the data lacks.
    ParticleFrames(const Scene& scene, const ParticleData& data);
    ~ParticleFrames();

    // Bounds of the spheres over all frames (positions grown by the largest radius).
    const Bounds& bounds() const { return m_bounds; }
    std::size_t particleCount() const { return m_maxCount; }

    // The sphere renderer for the scene (render.technique must be "spheres", or "raytraced" for
    // rt/raytraced_particles.h; anything else is an InputError: particles have no polylines). The context must be current. `firstFrame` is the
    // first animation frame to be rendered.
    std::unique_ptr<gl::Technique> createTechnique(int firstFrame);

    // Before rendering animation frame `frame`: uploads its data frame if it differs from the
    // one on the GPU (stage "upload", and "voxelize" with AO).
    void beforeFrame(int frame, gl::StageTimer& timer);

private:
    const Scene& m_scene;
    const ParticleData& m_data;
    Bounds m_bounds;
    std::size_t m_maxCount = 0;
    std::size_t m_current = 0;
    gl::SphereRenderer* m_renderer = nullptr;  // owned by the Technique createTechnique returned
    rt::RaytracedParticles* m_raytraced = nullptr;  // the same, for render.technique "raytraced"
};

}  // namespace tc::cli
