#include "test_scenes.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace tc::test {

StyledLines makeStyledLines(const std::vector<TestPolyline>& polylines) {
    StyledLines out;
    for (std::size_t p = 0; p < polylines.size(); ++p) {
        const TestPolyline& line = polylines[p];
        const auto first = std::uint32_t(out.positionRadius.size());
        for (std::size_t v = 0; v < line.size(); ++v) {
            const TestVertex& x = line[v];
            out.positionRadius.emplace_back(x.position, x.radius);
            out.color.push_back(x.color);
            out.polylineId.push_back(std::uint32_t(p));
            std::uint32_t flags = 0;
            if (v == 0) flags |= FirstOfPolyline;
            if (v + 1 == line.size()) flags |= LastOfPolyline;
            out.flags.push_back(flags);
            out.bounds.extend(x.position, x.radius);
            out.maxRadius = std::max(out.maxRadius, x.radius);
            if (v > 0) {
                out.segmentVertices.push_back(first + std::uint32_t(v) - 1);
                out.segmentVertices.push_back(first + std::uint32_t(v));
            }
        }
    }
    return out;
}

namespace {

// Uniform in [0, 1) from the top 24 bits of one mt19937 draw.
class Random {
public:
    explicit Random(std::uint32_t seed) : m_engine(seed) {}
    float uniform() { return float(m_engine() >> 8) * (1.0f / 16777216.0f); }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    int integer(int lo, int hi) { return lo + int(uniform() * float(hi - lo + 1)); }  // [lo, hi]
    glm::vec3 unitVector() {
        // Marsaglia-style: uniform z and azimuth give a uniform direction.
        float z = uniform(-1.0f, 1.0f), phi = uniform(0.0f, 6.2831853f);
        float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        return {s * std::cos(phi), s * std::sin(phi), z};
    }

private:
    std::mt19937 m_engine;
};

}  // namespace

StyledLines randomLineScene(std::uint32_t seed, const RandomSceneOptions& o) {
    Random rng(seed);
    std::vector<TestPolyline> polylines;
    for (int p = 0; p < o.polylines; ++p) {
        TestPolyline line;
        glm::vec3 x(rng.uniform(-o.extent, o.extent), rng.uniform(-o.extent, o.extent),
                    rng.uniform(-o.extent, o.extent));
        glm::vec3 dir = rng.unitVector();
        const int segments = rng.integer(o.minSegments, o.maxSegments);
        for (int v = 0; v <= segments; ++v) {
            float radius = o.radiusMin * std::pow(o.radiusRatio, rng.uniform());
            glm::vec4 color(rng.uniform(0.1f, 0.9f), rng.uniform(0.1f, 0.9f), rng.uniform(0.1f, 0.9f), 1.0f);
            line.push_back({x, radius, color});
            // Bend: rotate dir toward a random perpendicular by up to maxBendDeg.
            glm::vec3 perp = glm::cross(dir, rng.unitVector());
            if (glm::dot(perp, perp) < 1e-8f) perp = glm::cross(dir, glm::vec3(0.0f, 0.0f, 1.0f));
            perp = glm::normalize(perp);
            float bend = glm::radians(o.maxBendDeg) * rng.uniform();
            dir = glm::normalize(std::cos(bend) * dir + std::sin(bend) * perp);
            x += rng.uniform(o.stepMin, o.stepMax) * dir;
        }
        polylines.push_back(std::move(line));
    }
    return makeStyledLines(polylines);
}

Camera lookAt(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float fovYDeg) {
    Camera cam;
    cam.eye = eye;
    cam.target = target;
    cam.up = up;
    cam.fovYDeg = fovYDeg;
    return cam;
}

Camera orthographic(glm::vec3 eye, glm::vec3 target, float height, glm::vec3 up) {
    Camera cam = lookAt(eye, target, up);
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = height;
    return cam;
}

glm::vec3 eyeFromSeed(std::uint32_t seed, float distance) {
    const float phi = 2.399963f * float(seed), z = std::fmod(0.618034f * float(seed), 1.6f) - 0.8f;
    const float s = std::sqrt(1.0f - z * z);
    return distance * glm::vec3(s * std::cos(phi), z, s * std::sin(phi));
}

Scene vrcScene(int w, int h, int resolution, Transparency transparency) {
    Scene scene;
    scene.image.width = w;
    scene.image.height = h;
    scene.render.technique = RenderTechnique::VoxelRaycast;
    scene.render.transparency = transparency;
    scene.render.vrc.resolution = resolution;
    return scene;
}

}  // namespace tc::test
