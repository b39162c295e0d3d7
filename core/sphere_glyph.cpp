#include "core/sphere_glyph.h"

#include <algorithm>
#include <cmath>

#include "core/shading.h"
#include "core/sort_keys.h"

namespace tc {

SphereInterval intersectSphere(const Ray& ray, const glm::vec3& center, float radius) {
    SphereInterval s;
    const glm::vec3 oc = center - ray.origin;
    s.tClosest = glm::dot(oc, ray.dir);
    // The distance from the perpendicular foot, not |oc|^2 - t^2: no cancellation for far eyes.
    const glm::vec3 perp = oc - s.tClosest * ray.dir;
    s.dist2 = glm::dot(perp, perp);
    const float r2 = radius * radius;
    if (s.dist2 >= r2) return s;
    const float h = std::sqrt(r2 - s.dist2);
    s.tFar = s.tClosest + h;
    if (s.tFar <= 0.0f) return s;
    s.tNear = std::max(s.tClosest - h, 0.0f);
    s.hit = true;
    return s;
}

float densityNormalisation(SphereDensity model, float k) {
    switch (model) {
        case SphereDensity::Constant:
            return 2.0f;
        case SphereDensity::L2:
            return 2.0f * std::sqrt(2.0f) / 3.0f;
        case SphereDensity::HollowConstant:
            return 2.0f * std::sqrt(1.0f - k * k);
        case SphereDensity::HollowL2:
            return k <= 1.0f / std::sqrt(2.0f) ? 2.0f * std::sqrt(2.0f) / 3.0f
                                               : 2.0f / 3.0f * std::sqrt(1.0f - k * k) * (1.0f + 2.0f * k * k);
    }
    return 2.0f;
}

namespace {

// Integral of the density shape over [sn, sf] (ray parameters relative to the closest approach),
// unnormalised: constant -> length, l2 -> integral of d^2 + s^2.
float shapeIntegral(bool l2, float d2, float sn, float sf) {
    if (!l2) return sf - sn;
    return d2 * (sf - sn) + (sf * sf * sf - sn * sn * sn) / 3.0f;
}

}  // namespace

float unitOpticalDepth(SphereDensity model, float k, const SphereInterval& s, float radius) {
    if (!s.hit) return 0.0f;
    const bool l2 = model == SphereDensity::L2 || model == SphereDensity::HollowL2;
    const bool hollow = model == SphereDensity::HollowConstant || model == SphereDensity::HollowL2;
    const float sn = s.tNear - s.tClosest, sf = s.tFar - s.tClosest;
    float integral = shapeIntegral(l2, s.dist2, sn, sf);
    const float ri = k * radius;
    if (hollow && s.dist2 < ri * ri) {
        const float hi = std::sqrt(ri * ri - s.dist2);
        // The inner sphere's part of [sn, sf] (the eye may be inside the shell or the hole).
        const float a = std::max(-hi, sn), b = std::min(hi, sf);
        if (b > a) integral -= shapeIntegral(l2, s.dist2, a, b);
    }
    const float scale = l2 ? radius * radius * radius : radius;
    return std::max(integral / scale, 0.0f);
}

float sphereOpacity(float thetaMax, float T, float P) {
    if (T <= 0.0f) return 0.0f;
    if (thetaMax >= 1.0f) return 1.0f;
    return 1.0f - std::exp2(std::log2(1.0f - thetaMax) * (T / P));
}

float sphereRayOpacity(SphereDensity model, float k, float thetaMax, const Ray& ray, const glm::vec3& center,
                       float radius) {
    SphereInterval s = intersectSphere(ray, center, radius);
    return sphereOpacity(thetaMax, unitOpticalDepth(model, k, s, radius), densityNormalisation(model, k));
}

glm::vec3 sphereEmission(glm::vec3 base, glm::vec3 n, glm::vec3 dir, glm::vec3 lightDir, const LightingSpec& light,
                         float alphaRv, float alphaA, float ao, glm::vec3 ambientLight) {
    glm::vec3 surface = shadeBlinnPhong(base, n, dir, lightDir, light);
    // Staib et al. 2015, Eq. 2: L_RV = Theta ((1 - alpha_RV) L_R + alpha_RV c) (Theta: the caller's
    // premultiplication), then Eq. 7: A_O L_RV + alpha_A L_A.
    glm::vec3 c = ao * ((1.0f - alphaRv) * surface + alphaRv * base) + alphaA * ambientLight;
    return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f));
}

namespace {

// evaluateTransferFunction (core/styling.h) in the operation order of the GLSL twin
// (shaders/sphere_voxelize.comp), so the CPU and GPU volumes agree bit for bit.
float ambientTransferAt(const std::vector<glm::vec2>& points, float t) {
    if (t <= points.front().x) return points.front().y;
    for (std::size_t i = 1; i < points.size(); ++i)
        if (t <= points[i].x) {
            const float w = points[i].x - points[i - 1].x;
            if (!(w > 0.0f)) return points[i].y;
            const float s = (t - points[i - 1].x) / w;
            return points[i - 1].y * (1.0f - s) + points[i].y * s;
        }
    return points.back().y;
}

}  // namespace

glm::vec4 ambientClassify(const AmbientTransfer& transfer, const glm::vec4& color) {
    glm::vec4 c = color;
    if (!transfer.emission.empty())
        c = glm::vec4(glm::vec3(color) * ambientTransferAt(transfer.emission, color.w), c.w);
    if (!transfer.opacity.empty()) c.w = ambientTransferAt(transfer.opacity, color.w);
    return c;
}

nlohmann::json describeAmbientTransfer(const AmbientTransfer& transfer) {
    const auto points = [](const std::vector<glm::vec2>& p) {
        if (p.empty()) return nlohmann::json("primary");
        nlohmann::json j = nlohmann::json::array();
        for (const glm::vec2& q : p) j.push_back({q.x, q.y});
        return j;
    };
    return {{"opacity", points(transfer.opacity)}, {"emission", points(transfer.emission)}};
}

float powerDistance(const glm::vec3& eye, const glm::vec3& center, float radius) {
    const glm::vec3 d = center - eye;
    return glm::dot(d, d) - radius * radius;
}

std::uint32_t sphereSortKey(const glm::vec3& eye, bool orthographic, const glm::vec3& forward, const glm::vec3& center,
                            float radius) {
    return sortKeyFromFloat(orthographic ? glm::dot(center - eye, forward) : powerDistance(eye, center, radius));
}

bool projectedSphereBounds(const Camera& camera, float aspect, const glm::vec3& center, float radius, float pad,
                           glm::vec4& rect) {
    const glm::vec3 f = camera.forward(), rt = camera.right(), up = camera.trueUp();
    const glm::vec3 d = center - camera.eye;
    const float cx = glm::dot(d, rt), cy = glm::dot(d, up), cz = glm::dot(d, f);
    if (camera.projection == Projection::Orthographic) {
        // Orthographic rays start on the eye plane: a sphere wholly behind it is never hit.
        if (cz + radius <= 0.0f) return false;
        const float h = 0.5f * camera.orthoHeight;
        rect = glm::vec4((cx - radius) / (h * aspect), (cy - radius) / h, (cx + radius) / (h * aspect),
                         (cy + radius) / h) +
               glm::vec4(-pad, -pad, pad, pad);
        return true;
    }
    if (cz + radius <= 0.0f) return false;
    if (cz <= radius) {
        rect = glm::vec4(-1.0f, -1.0f, 1.0f, 1.0f);
        return true;
    }
    const float t = std::tan(glm::radians(camera.fovYDeg) * 0.5f);
    // Per axis, the two tangent lines from the eye to the circle (c_axis, cz): the direction to
    // the centre rotated by +-theta, sin(theta) = r / |c|. Their slopes bound the projection.
    auto bounds = [&](float c, float& lo, float& hi) {
        const float len2 = c * c + cz * cz;
        const float len = std::sqrt(len2);
        const float s = radius / len, co = std::sqrt(std::max(len2 - radius * radius, 0.0f)) / len;
        const float a = (c * co - cz * s) / (c * s + cz * co);
        const float b = (c * co + cz * s) / (cz * co - c * s);
        lo = std::min(a, b);
        hi = std::max(a, b);
    };
    float xlo, xhi, ylo, yhi;
    bounds(cx, xlo, xhi);
    bounds(cy, ylo, yhi);
    rect = glm::vec4(xlo / (t * aspect), ylo / t, xhi / (t * aspect), yhi / t) + glm::vec4(-pad, -pad, pad, pad);
    return true;
}

}  // namespace tc
