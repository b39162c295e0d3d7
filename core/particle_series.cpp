#include "core/particle_series.h"

#include <algorithm>

#include "core/particle_styling.h"

namespace tc {

float particleSeriesMaxRadius(const Scene& scene, const ParticleData& data) {
    const RadiusSpec& radius = scene.style.radius;
    float maxRadius = radius.attribute.empty() ? radius.constant : std::max(radius.radiusLo, radius.radiusHi);
    if (radius.attribute.empty() && !radius.fromScene)
        for (const ParticleSet& f : data.frames)
            for (float r : f.radii) maxRadius = std::max(maxRadius, r);
    return maxRadius;
}

Bounds particleSeriesBounds(const Scene& scene, const ParticleData& data) {
    const float maxRadius = particleSeriesMaxRadius(scene, data);
    Bounds out;
    const Bounds b = data.bounds();
    if (!b.empty()) {
        out.extend(b.lo, maxRadius);
        out.extend(b.hi, maxRadius);
    }
    return out;
}

bool anyTranslucent(const StyleSpec& style, const ParticleData& data) {
    const OpacitySpec& o = style.opacity;
    if (o.constant < 1.0f) return true;
    if (!o.attribute.empty()) {
        if (o.pointsFromColormap) return true;
        for (const glm::vec2& p : o.points)
            if (p.y < 1.0f) return true;
    }
    if (style.color.attribute.empty() && !style.color.fromScene)
        for (const ParticleSet& f : data.frames)
            for (const glm::vec4& c : f.colors)
                if (c.w < 1.0f) return true;
    return false;
}

ParticleSeriesTechnique::ParticleSeriesTechnique(const Scene& scene, const ParticleData& data, int firstFrame,
                                                 const Make& make)
    : m_style(scene.style), m_sceneFile(scene.file), m_pinned(scene.dataset.frame), m_data(data) {
    m_current = m_data.dataFrameFor(firstFrame, m_pinned);
    m_renderer = make(styleParticles(m_data.frames[m_current], m_style, m_sceneFile), m_upload);
}

void ParticleSeriesTechnique::prepareFrame(int frame, StageSink& sink) {
    const std::size_t wanted = m_data.dataFrameFor(frame, m_pinned);
    if (wanted == m_current || !m_upload) return;
    m_upload(styleParticles(m_data.frames[wanted], m_style, m_sceneFile), sink);
    m_current = wanted;
}

}  // namespace tc
