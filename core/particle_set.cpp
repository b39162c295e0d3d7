#include "core/particle_set.h"

#include <algorithm>

#include "core/error.h"

namespace tc {

const Attribute* ParticleSet::attribute(const std::string& name) const {
    for (const Attribute& a : attributes)
        if (a.name == name) return &a;
    return nullptr;
}

void ParticleSet::update() {
    bounds = Bounds{};
    for (const glm::vec3& p : positions) bounds.extend(p);
    for (Attribute& a : attributes) a.updateRange();
}

void ParticleSet::checkConsistent() const {
    const std::size_t n = positions.size();
    TC_CHECK(radii.empty() || radii.size() == n);
    TC_CHECK(colors.empty() || colors.size() == n);
    for (const Attribute& a : attributes) TC_CHECK_OP(a.values.size(), ==, n);
}

std::size_t dataFrameFor(std::size_t frameCount, int frame, int pinned) {
    if (frameCount == 0) return 0;
    const std::size_t last = frameCount - 1;
    const int wanted = pinned >= 0 ? pinned : std::max(frame, 0);
    return std::min(std::size_t(wanted), last);
}

std::size_t ParticleData::dataFrameFor(int frame, int pinned) const {
    return tc::dataFrameFor(frames.size(), frame, pinned);
}

Bounds ParticleData::bounds() const {
    Bounds b;
    for (const ParticleSet& f : frames)
        if (!f.bounds.empty()) {
            b.extend(f.bounds.lo);
            b.extend(f.bounds.hi);
        }
    return b;
}

std::size_t ParticleData::maxParticles() const {
    std::size_t n = 0;
    for (const ParticleSet& f : frames) n = std::max(n, f.size());
    return n;
}

}  // namespace tc
