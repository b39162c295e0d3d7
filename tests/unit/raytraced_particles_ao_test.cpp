// Ambient occlusion of ray-traced particles (rt/particle_ambient.h): the CPU sphere volume, the
// cone-traced A_O / L_A (cached per sphere or per point) and the hemisphere rays, on scenes whose
// answer is known: an isolated sphere is unoccluded, the centre of a dense cluster is darker than
// its surface, and images do not depend on the thread count. (The agreement with the GL spheres
// technique's AO is tests/cli/raytraced_cli_test.cpp.)
#include <embree3/rtcore.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

#include "rt/particle_ambient.h"
#include "rt/raytraced_particles.h"

namespace tc {
namespace {

// A cubic lattice of n^3 touching-free spheres of radius r, spacing d, centred on the origin, plus
// optionally one sphere far outside it.
StyledParticles lattice(int n, float r, float d, glm::vec4 color) {
    StyledParticles s;
    const float c0 = -0.5f * d * float(n - 1);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::vec4 cr(c0 + d * float(x), c0 + d * float(y), c0 + d * float(z), r);
                s.centerRadius.push_back(cr);
                s.color.push_back(color);
                s.id.push_back(std::uint32_t(s.size()));
                s.bounds.extend(glm::vec3(cr), r);
                s.maxRadius = r;
            }
    return s;
}

// The particles as Embree sphere points (what RaytracedParticles builds), for the ray-traced AO.
struct SphereScene {
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    explicit SphereScene(const StyledParticles& p) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<glm::vec4*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, sizeof(glm::vec4), p.size()));
        for (std::size_t i = 0; i < p.size(); ++i) v[i] = p.centerRadius[i];
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene);
    }
    ~SphereScene() {
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
    }
};

AoSpec aoSpec(AoSpec::Method method, AoSpec::Cache cache) {
    AoSpec a;
    a.enabled = true;
    a.method = method;
    a.cache = cache;
    a.resolution = 64;
    a.samples = 64;
    a.distance = 0.25f;
    return a;
}

const std::vector<std::pair<AoSpec::Method, AoSpec::Cache>> kVariants = {
    {AoSpec::Method::ConeTraced, AoSpec::Cache::None},
    {AoSpec::Method::ConeTraced, AoSpec::Cache::Precomputed},
    {AoSpec::Method::RayTraced, AoSpec::Cache::None}};

const char* name(AoSpec::Method m, AoSpec::Cache c) {
    if (m == AoSpec::Method::RayTraced) return "ray_traced";
    return c == AoSpec::Cache::None ? "cone_traced per point" : "cone_traced cached";
}

TEST(RaytracedParticlesAo, an_isolated_sphere_is_unoccluded_everywhere) {
    // Sphere 0 at the origin and sphere 1 far beyond the AO distance (0.25 of the bounds'
    // diagonal), both of radius ~1.5 voxels: particles are small against the grid. (A sphere that
    // fills the whole grid occludes itself through the coarse mip levels, in the GL technique too.)
    StyledParticles p = lattice(2, 0.03f, 1.0f, {0.8f, 0.4f, 0.2f, 0.9f});
    p.centerRadius.resize(2);
    p.color.resize(2);
    p.id.resize(2);
    p.bounds = {};
    for (const glm::vec4& cr : p.centerRadius) p.bounds.extend(glm::vec3(cr), cr.w);
    SphereScene embree(p);
    for (auto [method, cache] : kVariants) {
        rt::ParticleAmbient amb(aoSpec(method, cache), SpheresSpec{}, false, p, embree.scene);
        float minAo = 1.0f, maxLight = 0.0f;
        for (int k = 0; k < 64; ++k) {
            // Normals spread over the sphere (a spherical Fibonacci set).
            const float z = 1.0f - (float(k) + 0.5f) / 32.0f, rho = std::sqrt(std::max(0.0f, 1.0f - z * z));
            const float phi = 2.39996323f * float(k);
            const glm::vec3 n(rho * std::cos(phi), rho * std::sin(phi), z);
            const rt::AmbientTerms t = amb.at(0, glm::vec3(p.centerRadius[0]) + 0.03f * n, n, std::uint32_t(k));
            minAo = std::min(minAo, t.ao);
            maxLight = std::max({maxLight, t.light.x, t.light.y, t.light.z});
        }
        std::cout << name(method, cache) << ": isolated sphere A_O >= " << minAo << ", L_A <= " << maxLight << "\n";
        if (method == AoSpec::Method::RayTraced) {
            EXPECT_EQ(minAo, 1.0f);  // no other sphere: every ray escapes
            EXPECT_EQ(maxLight, 0.0f);
        } else {
            // The cones start 1.5 voxels out; what they still see of the sphere itself is its
            // coverage blurred into the coarse mip levels (the GL technique's, by construction).
            EXPECT_GT(minAo, 0.9f) << name(method, cache);
        }
    }
}

TEST(RaytracedParticlesAo, the_centre_of_a_dense_cluster_is_darker_than_its_surface) {
    // 9^3 spheres, radius 0.04 at spacing 0.1 (about a third of the volume filled).
    const int n = 9;
    StyledParticles p = lattice(n, 0.04f, 0.1f, {0.2f, 0.6f, 0.9f, 1.0f});
    SphereScene embree(p);
    const std::uint32_t centre = std::uint32_t((n / 2 * n + n / 2) * n + n / 2);
    const std::uint32_t surface = std::uint32_t((n / 2 * n + n / 2) * n + (n - 1));  // on the +x face
    const glm::vec3 x(1.0f, 0.0f, 0.0f);
    for (auto [method, cache] : kVariants) {
        rt::ParticleAmbient amb(aoSpec(method, cache), SpheresSpec{}, true, p, embree.scene);
        auto at = [&](std::uint32_t s) {
            const glm::vec4 cr = p.centerRadius[s];
            return amb.at(s, glm::vec3(cr) + cr.w * x, x, 7u);
        };
        const rt::AmbientTerms inner = at(centre), outer = at(surface);
        std::cout << name(method, cache) << ": A_O centre " << inner.ao << ", surface (facing out) " << outer.ao
                  << "; L_A centre " << inner.light.z << ", surface " << outer.light.z << "\n";
        EXPECT_LT(inner.ao, outer.ao - 0.2f) << name(method, cache);
        EXPECT_GT(outer.ao, 0.8f) << name(method, cache);  // facing out of the cluster
        // The light reflected onto the inner sphere comes from its (blue) neighbours.
        EXPECT_GT(inner.light.z, inner.light.x) << name(method, cache);
        EXPECT_GT(inner.light.z, outer.light.z) << name(method, cache);
    }
}

// Staib et al. 2015, Sect. 3.2: the ambient transfer functions (render.spheres.ambient_*) act on
// the ambient terms only, in every AO variant of the CPU twin: ambient opacity 0 leaves nothing
// to occlude (A_O = 1, L_A = 0), ambient emission 0 keeps A_O and removes L_A, and a partial
// ambient opacity lightens the centre of the cluster (measured: A_O 1.9x to 10x as large).
TEST(RaytracedParticlesAo, ambient_transfer_functions_set_the_ambient_opacity_and_emission) {
    const int n = 9;
    StyledParticles p = lattice(n, 0.04f, 0.1f, {0.2f, 0.6f, 0.9f, 0.8f});
    SphereScene embree(p);
    const std::uint32_t centre = std::uint32_t((n / 2 * n + n / 2) * n + n / 2);
    const glm::vec3 x(1.0f, 0.0f, 0.0f);
    const std::vector<glm::vec2> zero{{0.0f, 0.0f}, {1.0f, 0.0f}};
    for (auto [method, cache] : kVariants) {
        for (bool opaque : {true, false}) {
            auto at = [&](const AmbientTransfer& transfer) {
                SpheresSpec spheres;
                spheres.ambient = transfer;
                rt::ParticleAmbient amb(aoSpec(method, cache), spheres, opaque, p, embree.scene);
                const glm::vec4 cr = p.centerRadius[centre];
                return amb.at(centre, glm::vec3(cr) + cr.w * x, x, 7u);
            };
            AmbientTransfer noOpacity, noEmission, half;
            noOpacity.opacity = zero;
            noEmission.emission = zero;
            half.opacity = {{0.0f, 0.0f}, {1.0f, 0.5f}};
            const rt::AmbientTerms base = at({}), none = at(noOpacity), dark = at(noEmission), light = at(half);
            const std::string label = std::string(name(method, cache)) + (opaque ? ", opaque" : ", transparent");
            EXPECT_LT(base.ao, 0.8f) << label;
            EXPECT_GT(base.light.z, 0.01f) << label;
            EXPECT_EQ(none.ao, 1.0f) << label;
            EXPECT_EQ(none.light, glm::vec3(0.0f)) << label;
            EXPECT_EQ(dark.ao, base.ao) << label;
            EXPECT_EQ(dark.light, glm::vec3(0.0f)) << label;
            std::cout << label << ": A_O " << base.ao << ", ambient opacity x 0.5: " << light.ao << "\n";
            EXPECT_GT(light.ao, 1.5f * base.ao + 0.01f) << label;
        }
    }
}

TEST(RaytracedParticlesAo, images_with_ao_are_identical_with_one_and_two_threads) {
    StyledParticles p = lattice(6, 0.06f, 0.15f, {0.9f, 0.5f, 0.3f, 0.5f});
    for (std::size_t i = 0; i < p.size(); ++i) p.color[i].x = float(i % 7) / 7.0f;  // varied colours
    Camera cam;
    cam.eye = {0.9f, 0.7f, 1.6f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 45.0f;
    for (Transparency t : {Transparency::Opaque, Transparency::ObjectOrder})
        for (auto [method, cache] : kVariants) {
            Scene scene;
            scene.render.technique = RenderTechnique::Raytraced;
            scene.render.transparency = t;
            scene.render.raytracedAlphaCutoff = 0.99f;
            scene.render.ao = aoSpec(method, cache);
            scene.render.ao.samples = 16;
            std::vector<FrameImages> images;
            for (int threads : {1, 2}) {
                tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
                auto r = rt::RaytracedParticles::create(scene, p);
                FrameImages img;
                tc::CpuStageTimer timer;
                r->render(cam, 40, 30, img, timer);
                images.push_back(std::move(img));
            }
            EXPECT_EQ(images[0].rgba, images[1].rgba) << name(method, cache);
            EXPECT_EQ(images[0].ao, images[1].ao) << name(method, cache);
            EXPECT_EQ(images[0].ao.empty(), t != Transparency::Opaque);
            if (t == Transparency::Opaque) {
                // Some pixels are occluded (the lattice), none above 1.
                float lo = 1.0f, hi = 0.0f;
                for (float a : images[0].ao) lo = std::min(lo, a), hi = std::max(hi, a);
                EXPECT_LT(lo, 0.9f) << name(method, cache);
                // (The ambient cube's blend weights n^2 sum to 1 up to the rounding of n.)
                EXPECT_LE(hi, 1.0f + 1e-4f) << name(method, cache);
            }
        }
}

}  // namespace
}  // namespace tc
