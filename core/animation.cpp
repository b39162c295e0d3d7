#include "core/animation.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <set>

#include "core/error.h"

namespace tc {

Camera fitCamera(const CameraSpec& spec, const Bounds& bounds, float aspect) {
    Camera camera = spec.camera;
    if (!spec.fit || bounds.empty()) return camera;
    glm::vec3 direction = glm::normalize(camera.eye - camera.target);
    float radius = std::max(bounds.radius(), 1e-6f);
    camera.target = bounds.center();
    // 3 % margin so silhouettes do not touch the image border.
    constexpr float kMargin = 1.03f;
    if (camera.projection == Projection::Orthographic) {
        camera.orthoHeight = 2.0f * radius * kMargin * std::max(1.0f, 1.0f / aspect);
        camera.eye = camera.target + direction * (3.0f * radius);
    } else {
        float halfY = glm::radians(camera.fovYDeg) * 0.5f;
        float halfX = std::atan(std::tan(halfY) * aspect);
        float half = std::min(halfX, halfY);
        camera.eye = camera.target + direction * (kMargin * radius / std::sin(half));
    }
    return camera;
}

namespace {

// Catmull-Rom for keys at uneven frames: cubic Hermite whose tangent at a key is the mean of the
// slopes (per frame) of its two neighbouring intervals, a missing neighbour contributing 0. With
// uniform spacing this is exactly the uniform Catmull-Rom spline with repeated end keys; with
// uneven spacing the velocity per frame stays continuous across keys (uniform Catmull-Rom in
// the per-segment parameter would jump by the ratio of the two spacings).
glm::vec3 keyTangent(const glm::vec3& p0, float f0, const glm::vec3& p1, float f1, const glm::vec3& p2, float f2) {
    glm::vec3 left = f1 > f0 ? (p1 - p0) / (f1 - f0) : glm::vec3(0.0f);
    glm::vec3 right = f2 > f1 ? (p2 - p1) / (f2 - f1) : glm::vec3(0.0f);
    return 0.5f * (left + right);
}

glm::vec3 catmullRom(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3, float f0,
                     float f1, float f2, float f3, float frame) {
    float h = f2 - f1, t = (frame - f1) / h, t2 = t * t, t3 = t2 * t;
    glm::vec3 m1 = h * keyTangent(p0, f0, p1, f1, p2, f2);
    glm::vec3 m2 = h * keyTangent(p1, f1, p2, f2, p3, f3);
    return (2.0f * t3 - 3.0f * t2 + 1.0f) * p1 + (t3 - 2.0f * t2 + t) * m1 + (-2.0f * t3 + 3.0f * t2) * p2 +
           (t3 - t2) * m2;
}

}  // namespace

Camera cameraAtFrame(const AnimationSpec& animation, const Camera& base, int frame) {
    Camera camera = base;
    switch (animation.type) {
        case AnimationSpec::Type::None:
            return camera;
        case AnimationSpec::Type::Orbit: {
            float angle = glm::radians(animation.degrees) * float(frame) / float(animation.frames);
            glm::vec3 axis = glm::normalize(animation.axis);
            glm::quat rotation = glm::angleAxis(angle, axis);
            camera.eye = base.target + rotation * (base.eye - base.target);
            camera.up = rotation * base.up;
            return camera;
        }
        case AnimationSpec::Type::Keyframes: {
            const auto& keys = animation.keys;
            auto apply = [&](const Keyframe& k) {
                camera.eye = k.eye;
                camera.target = k.target;
                camera.up = k.up;
                return camera;
            };
            if (frame <= keys.front().frame) return apply(keys.front());
            if (frame >= keys.back().frame) return apply(keys.back());
            std::size_t i = 0;
            while (keys[i + 1].frame <= frame) ++i;
            const Keyframe& k1 = keys[i];
            const Keyframe& k2 = keys[i + 1];
            const Keyframe& k0 = keys[i == 0 ? 0 : i - 1];
            const Keyframe& k3 = keys[std::min(i + 2, keys.size() - 1)];
            const float f0 = float(k0.frame), f1 = float(k1.frame), f2 = float(k2.frame), f3 = float(k3.frame);
            const float f = float(frame);
            camera.eye = catmullRom(k0.eye, k1.eye, k2.eye, k3.eye, f0, f1, f2, f3, f);
            camera.target = catmullRom(k0.target, k1.target, k2.target, k3.target, f0, f1, f2, f3, f);
            glm::vec3 up = catmullRom(k0.up, k1.up, k2.up, k3.up, f0, f1, f2, f3, f);
            camera.up = glm::length(up) > 1e-6f ? glm::normalize(up) : k1.up;
            return camera;
        }
    }
    return camera;
}

std::vector<int> parseFrameList(const std::string& spec, int frameCount) {
    std::vector<int> all;
    if (spec.empty() || spec == "all") {
        for (int i = 0; i < frameCount; ++i) all.push_back(i);
        return all;
    }
    auto fail = [&](const std::string& why) -> void { throw InputError("--frames " + spec + ": " + why); };
    auto number = [&](const std::string& text) {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
            fail("expected a frame number, got \"" + text + "\" (syntax: 0..99, 0..99:5, 3,7,12..20)");
        if (text.size() > 9) fail("frame number \"" + text + "\" is too large");
        return std::stoi(text);
    };
    std::set<int> frames;
    std::size_t start = 0;
    while (start <= spec.size()) {
        std::size_t comma = spec.find(',', start);
        std::string item = spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        int step = 1;
        if (auto colon = item.find(':'); colon != std::string::npos) {
            step = number(item.substr(colon + 1));
            if (step < 1) fail("step must be >= 1");
            item = item.substr(0, colon);
        }
        int first, last;
        if (auto dots = item.find(".."); dots != std::string::npos) {
            first = number(item.substr(0, dots));
            last = number(item.substr(dots + 2));
            if (last < first) fail("range " + item + " ends before it starts");
        } else {
            first = last = number(item);
        }
        if (last >= frameCount)
            fail("frame " + std::to_string(last) + " is outside the animation's frames 0.." +
                 std::to_string(frameCount - 1));
        for (int f = first; f <= last; f += step) frames.insert(f);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return {frames.begin(), frames.end()};
}

}  // namespace tc
