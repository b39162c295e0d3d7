#include "cli/particle_frames.h"

#include <algorithm>

#include "core/error.h"
#include "core/particle_styling.h"
#include "cli/technique_factory.h"
#include "gl/gpu_timer.h"
#include "gl/sphere_renderer.h"
#include "rt/raytraced_particles.h"

namespace tc::cli {

ParticleFrames::ParticleFrames(const Scene& scene, const ParticleData& data) : m_scene(scene), m_data(data) {
    // Bounds over all frames without styling them all: the positions' union grown by the largest
    // radius the style or the data can give.
    float maxRadius = scene.style.radius.attribute.empty() ? scene.style.radius.constant
                                                           : std::max(scene.style.radius.radiusLo, scene.style.radius.radiusHi);
    for (const ParticleSet& f : data.frames) {
        m_maxCount = std::max(m_maxCount, f.size());
        if (scene.style.radius.attribute.empty())
            for (float r : f.radii) maxRadius = std::max(maxRadius, r);
    }
    Bounds b = data.bounds();
    if (!b.empty()) {
        m_bounds.extend(b.lo, maxRadius);
        m_bounds.extend(b.hi, maxRadius);
    }
}

ParticleFrames::~ParticleFrames() = default;

std::unique_ptr<gl::Technique> ParticleFrames::createTechnique(int firstFrame) {
    if (m_scene.render.technique != RenderTechnique::Spheres && m_scene.render.technique != RenderTechnique::Raytraced)
        throw InputError((m_scene.file.empty() ? std::string("scene") : m_scene.file) +
                         ": render.technique: a particle dataset needs \"spheres\" or \"raytraced\"");
    m_current = m_data.dataFrameFor(firstFrame, m_scene.dataset.frame);
    StyledParticles styled = styleParticles(m_data.frames[m_current], m_scene.style, m_scene.file);
    if (m_scene.render.technique == RenderTechnique::Raytraced) return makeRaytracedParticles(m_scene, styled, m_raytraced);
    auto renderer = gl::SphereRenderer::create(m_scene, styled);
    m_renderer = renderer.get();
    return renderer;
}

void ParticleFrames::beforeFrame(int frame, gl::StageTimer& timer) {
    const std::size_t wanted = m_data.dataFrameFor(frame, m_scene.dataset.frame);
    if (wanted == m_current || (!m_renderer && !m_raytraced)) return;
    StyledParticles styled = styleParticles(m_data.frames[wanted], m_scene.style, m_scene.file);
    if (m_raytraced) {
        timer.begin("upload");  // the BVH rebuild
        m_raytraced->upload(styled);
        timer.setItems(styled.size());
        timer.end();
    } else {
        m_renderer->upload(styled, timer);
    }
    m_current = wanted;
}

}  // namespace tc::cli
