#pragma once
// Transparent sphere glyphs (Staib, Grottel & Gumhold 2015): the ray-sphere interval, the
// analytic opacity of the density models (Sect. 4), the emission of Eq. 2 / Eq. 7, the power-
// distance sort key and the projected bounds of a sphere. shaders/sphere_glyph.glsl is the GLSL
// twin of every function here (same formulas, same operation order); keep them in lock-step.
//
// Opacity. A density model gives the extinction along a ray through a sphere of radius r; its
// integral over the ray's interval inside the sphere, in units of r, is the optical depth T
// (unitOpticalDepth). P = the largest T over all rays (densityNormalisation) belongs to the most
// opaque ray, which gets the particle's opacity Theta_max (style.opacity): the extinction scale is
// lambda = -ln(1 - Theta_max) / (r P) (Eq. 15 for the constant model), so a ray's opacity is
//     alpha = 1 - exp(-lambda r T) = 1 - (1 - Theta_max)^(T / P)                  (Eq. 14, 18)
//   constant:  density lambda              T = (t_f - t_n) / r,                   P = 2
//   l2:        density lambda |x - c|^2/r^2 T = (d^2 (s_f - s_n) + (s_f^3 - s_n^3) / 3) / r^3,
//              with s = t - t_c (t_c the ray's closest approach, d its distance), P = 2 sqrt(2) / 3,
//              reached at d = r / sqrt(2) (Eq. 19)
//   hollow:    the same densities, zero inside the inner sphere of radius k r (Sect. 4.3): T of the
//              outer interval minus T of the inner one (the two intervals of the shell carry the
//              same colour, so compositing them is adding their optical depths);
//              P = 2 sqrt(1 - k^2) (constant, at d = k r), l2: 2 sqrt(2)/3 for k <= 1/sqrt(2),
//              else (2/3) sqrt(1 - k^2)(1 + 2 k^2) (at d = k r).
#include <cstdint>
#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/scene.h"

namespace tc {

// The ray's interval inside a sphere. tNear is clamped to 0 (the ray starts at the eye, or on the
// eye plane for orthographic rays); tClosest is the ray parameter of the closest approach to the
// centre and dist2 the squared distance there.
struct SphereInterval {
    bool hit = false;
    float tNear = 0, tFar = 0, tClosest = 0, dist2 = 0;
};
SphereInterval intersectSphere(const Ray& ray, const glm::vec3& center, float radius);

float densityNormalisation(SphereDensity model, float innerRatio);

// T of the interval [tNear, tFar] (from intersectSphere), in units of the radius.
float unitOpticalDepth(SphereDensity model, float innerRatio, const SphereInterval& s, float radius);

// alpha = 1 - (1 - thetaMax)^(T / P); thetaMax = 1 gives 1 for any T > 0 (the opaque limit).
float sphereOpacity(float thetaMax, float T, float P);

// Opacity of one ray through one sphere (0 when it misses).
float sphereRayOpacity(SphereDensity model, float innerRatio, float thetaMax, const Ray& ray, const glm::vec3& center,
                       float radius);

// Emission of a particle at a ray's entry point (Eq. 2 and 7): the Blinn-Phong surface term
// (core/shading.h, normal n at the entry) mixed with the volume emission `base` by alphaRv,
// (1 - alphaRv) surface + alphaRv base (alphaRv = 0: the surface alone, 1: the particle colour
// alone), times the ambient occlusion factor ao, plus alphaA times the coloured ambient light. Clamped to
// [0, 1] like every blended colour. All linear RGB, not premultiplied.
glm::vec3 sphereEmission(glm::vec3 base, glm::vec3 n, glm::vec3 dir, glm::vec3 lightDir, const LightingSpec& light,
                         float alphaRv, float alphaA, float ao, glm::vec3 ambientLight);

// The particle as the ambient volume sees it (Staib et al. 2015, Sect. 3.2 and 5: the ambient
// transfer functions, applied at voxelization): colour x e_A(Theta) and opacity Theta_A(Theta),
// Theta = color.a; an empty function is the identity (the primary transfer function). The GLSL
// twin is ambientClassify in shaders/sphere_voxelize.comp.
glm::vec4 ambientClassify(const AmbientTransfer& transfer, const glm::vec4& color);
// For run.json: each function's points, or "primary" when it is the identity.
nlohmann::json describeAmbientTransfer(const AmbientTransfer& transfer);

// Power distance |c - e|^2 - r^2 of the eye to the sphere: sorting disjoint spheres by it gives
// the exact visibility order for any radii; negative when the eye is inside the sphere.
float powerDistance(const glm::vec3& eye, const glm::vec3& center, float radius);

// The sort key of a sphere: sortKeyFromFloat (core/sort_keys.h, order preserving, negatives first)
// of the power distance (perspective) or of the centre's view depth dot(c - eye, forward)
// (orthographic: the limit of the power distance order for an eye at infinity).
std::uint32_t sphereSortKey(const glm::vec3& eye, bool orthographic, const glm::vec3& forward, const glm::vec3& center,
                            float radius);

// NDC rectangle (xmin, ymin, xmax, ymax) containing the projection of the sphere exactly (the
// tangent planes through the eye, so perspective-correct), grown by `pad` NDC units. A sphere that
// reaches the eye plane projects without bound: the whole viewport. Returns false for a sphere
// entirely behind the eye plane (nothing to draw).
bool projectedSphereBounds(const Camera& camera, float aspect, const glm::vec3& center, float radius, float pad,
                           glm::vec4& rect);

}  // namespace tc
