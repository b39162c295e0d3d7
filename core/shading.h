#pragma once
// Blinn-Phong shading of tube surfaces, identical on CPU and GPU (shaders/shading.glsl is the twin
// of this file; keep them in lock-step).
#include <cmath>
#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/scene.h"

namespace tc {

// LightingSpec::direction is in camera space (camera looking down -z; (0,0,1) = from the
// viewer): the unit world-space direction toward the light.
inline glm::vec3 lightDirectionWorld(const LightingSpec& light, const Camera& camera) {
    glm::vec3 lc = glm::normalize(light.direction);
    return glm::normalize(lc.x * camera.right() + lc.y * camera.trueUp() - lc.z * camera.forward());
}

// x^e for the specular lobe, x in [0, 1]. A whole exponent up to 1024 (lighting.shininess is 32
// unless set) by repeated squaring: at most 2 log2(e) products, relative error below e x 2^-24
// (2e-6 at 32, far below one 8-bit step), at a fraction of libm's powf, which was the largest part
// of shading a ray-traced hit (`perf report` of tubecast_raytraced_bench); any other exponent by
// std::pow. (GLSL's pow in shaders/shading.glsl is exp2(e log2 x) to the driver's precision: the
// twins agreed to float rounding before and do now.)
inline float specularPower(float x, float e) {
    const int n = int(e);
    if (float(n) != e || n < 1 || n > 1024) return std::pow(x, e);
    float result = 1.0f;
    for (unsigned k = unsigned(n);;) {
        if (k & 1u) result *= x;
        k >>= 1;
        if (k == 0) return result;
        x *= x;
    }
}

// Two-sided Blinn-Phong: base (linear RGB), n the outward unit normal, dir the unit ray direction
// (eye -> point), lightDir the unit world direction toward the light. The normal is flipped to
// face the viewer, so the inside wall of a tube the eye is in is lit like the outside.
// Returns linear RGB, not premultiplied.
inline glm::vec3 shadeBlinnPhong(glm::vec3 base, glm::vec3 n, glm::vec3 dir, glm::vec3 lightDir, float ambient,
                                 float diffuse, float specular, float shininess) {
    glm::vec3 v = -dir;
    glm::vec3 nf = glm::dot(n, v) >= 0.0f ? n : -n;
    float ndl = glm::dot(nf, lightDir);
    glm::vec3 color = base * (ambient + diffuse * glm::max(ndl, 0.0f));
    // ndl > 0 and dot(nf, v) >= 0 imply lightDir != -v, so the half vector is defined.
    if (ndl > 0.0f) {
        glm::vec3 h = glm::normalize(lightDir + v);
        color += glm::vec3(specular * specularPower(glm::max(glm::dot(nf, h), 0.0f), shininess));
    }
    return color;
}

inline glm::vec3 shadeBlinnPhong(glm::vec3 base, glm::vec3 n, glm::vec3 dir, glm::vec3 lightDir,
                                 const LightingSpec& light) {
    return shadeBlinnPhong(base, n, dir, lightDir, light.ambient, light.diffuse, light.specular, light.shininess);
}

}  // namespace tc
