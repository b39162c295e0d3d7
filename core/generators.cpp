#include "core/generators.h"

#include <cmath>
#include <random>

#include <tbb/parallel_for.h>

namespace tc {

glm::vec3 tornadoVelocity(const glm::vec3& p) {
    // Crawfis' gen_tornado at time 0, evaluated continuously instead of on a grid.
    const float x = p.x, y = p.y, z = p.z;
    float xc = 0.5f + 0.1f * std::sin(10.0f * z);
    float yc = 0.5f + 0.1f * std::cos(3.0f * z);
    float r = 0.1f + 0.4f * z * z + 0.1f * z * std::sin(8.0f * z);
    float r2 = 0.2f + 0.1f * z;
    float temp = std::sqrt((y - yc) * (y - yc) + (x - xc) * (x - xc));
    float scale = std::abs(r - temp);
    scale = scale > r2 ? 0.8f - scale : 1.0f;
    float z0 = std::max(0.0f, 0.1f * (0.1f - temp * z));
    temp = std::sqrt(temp * temp + z0 * z0);
    scale = (r + r2 - temp) * scale / (temp + 1e-11f);
    scale = scale / (1.0f + z);
    return {scale * (y - yc) + 0.1f * (x - xc), scale * -(x - xc) + 0.1f * (y - yc), scale * z0 + 0.05f};
}

namespace {

// One streamline: RK4 on the unit-speed direction field, so vertices are evenly spaced.
std::vector<glm::vec3> trace(glm::vec3 p, int points, float step) {
    std::vector<glm::vec3> line;
    line.reserve(std::size_t(points));
    line.push_back(p);
    auto dir = [](const glm::vec3& q) {
        glm::vec3 v = tornadoVelocity(q);
        float len = glm::length(v);
        return len > 1e-6f ? v / len : glm::vec3(0.0f);
    };
    auto inside = [](const glm::vec3& q) {
        return q.x >= 0.0f && q.x <= 1.0f && q.y >= 0.0f && q.y <= 1.0f && q.z >= 0.0f && q.z <= 1.0f;
    };
    while (int(line.size()) < points) {
        glm::vec3 k1 = dir(p);
        glm::vec3 k2 = dir(p + 0.5f * step * k1);
        glm::vec3 k3 = dir(p + 0.5f * step * k2);
        glm::vec3 k4 = dir(p + step * k3);
        glm::vec3 next = p + step / 6.0f * (k1 + 2.0f * k2 + 2.0f * k3 + k4);
        if (!inside(next) || glm::length(next - p) < 0.25f * step) break;
        line.push_back(next);
        p = next;
    }
    return line;
}

}  // namespace

LineSet generateTornado(int lines, int points, std::uint32_t seed) {
    // Arc-length step: a streamline of `points` vertices covers about 1.5 turns of the vortex
    // at any resolution.
    const float step = 3.0f / float(std::max(points - 1, 1));
    std::vector<std::vector<glm::vec3>> traced(static_cast<std::size_t>(lines));
    tbb::parallel_for(0, lines, [&](int i) {
        std::mt19937 rng(seed * 0x9E3779B9u + std::uint32_t(i));
        std::uniform_real_distribution<float> u(0.05f, 0.95f);
        std::vector<glm::vec3> best;
        for (int attempt = 0; attempt < 32 && int(best.size()) < points; ++attempt) {
            glm::vec3 p{u(rng), u(rng), 0.9f * u(rng) * u(rng)};  // more seeds low in the funnel
            auto line = trace(p, points, step);
            if (line.size() > best.size()) best = std::move(line);
        }
        traced[std::size_t(i)] = std::move(best);
    });

    LineSet set;
    Attribute speed{"speed", {}}, height{"height", {}}, arc{"arc_length", {}};
    for (const auto& line : traced) {
        if (line.size() < 2) continue;
        float s = 0.0f;
        for (std::size_t k = 0; k < line.size(); ++k) {
            if (k > 0) s += glm::length(line[k] - line[k - 1]);
            set.positions.push_back(line[k]);
            speed.values.push_back(glm::length(tornadoVelocity(line[k])));
            height.values.push_back(line[k].z);
            arc.values.push_back(s);
        }
        set.offsets.push_back(std::uint32_t(set.positions.size()));
    }
    set.attributes = {std::move(speed), std::move(height), std::move(arc)};
    for (auto& a : set.attributes) a.updateRange();
    set.updateBounds();
    return set;
}

}  // namespace tc
