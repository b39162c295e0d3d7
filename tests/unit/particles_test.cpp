// Particles (Staib, Grottel & Gumhold 2015): density-model opacity against closed forms, the
// power-distance sort key, projected sphere bounds, the droplets generator, particle styling, the
// CPU reference compositor and the render.spheres scene keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.h"
#include "core/particle_generators.h"
#include "core/particle_reference.h"
#include "core/particle_styling.h"
#include "core/scene.h"
#include "core/shading.h"
#include "core/sort_keys.h"
#include "core/sphere_glyph.h"

namespace tc {
namespace {

// An orthographic ray along -z at distance d from the centre of a sphere at the origin.
Ray rayAtDistance(float d) {
    return Ray{{d, 0.0f, 10.0f}, {0.0f, 0.0f, -1.0f}};
}

float opacityAt(SphereDensity model, float k, float theta, float d, float r) {
    return sphereRayOpacity(model, k, theta, rayAtDistance(d), glm::vec3(0.0f), r);
}

TEST(SphereOpacity, constant_model_reaches_theta_max_at_the_centre_and_follows_eq14) {
    const float r = 0.7f;
    for (float theta : {0.1f, 0.3f, 0.9f}) {
        EXPECT_NEAR(opacityAt(SphereDensity::Constant, 0, theta, 0.0f, r), theta, 1e-6f);
        // Eq. 14/15: lambda = -ln(1 - theta) / (2 r); alpha = 1 - exp(-lambda * chord).
        const float lambda = -std::log(1.0f - theta) / (2.0f * r);
        for (float d : {0.1f, 0.35f, 0.6f, 0.69f}) {
            const float chord = 2.0f * std::sqrt(r * r - d * d);
            EXPECT_NEAR(opacityAt(SphereDensity::Constant, 0, theta, d, r), 1.0f - std::exp(-lambda * chord), 2e-6f)
                << d;
        }
    }
    EXPECT_EQ(opacityAt(SphereDensity::Constant, 0, 0.5f, 0.71f, r), 0.0f);  // a miss
    EXPECT_EQ(opacityAt(SphereDensity::Constant, 0, 1.0f, 0.5f, r), 1.0f);   // opaque limit
}

TEST(SphereOpacity, l2_model_peaks_at_r_over_sqrt2_with_theta_max_and_matches_eq18) {
    const float r = 2.0f, theta = 0.6f;
    // Closed form: density lambda |x - c|^2 / r^2 integrated over the chord at distance d is
    // lambda (2 h / 3)(r^2 + 2 d^2) / r^2, h = sqrt(r^2 - d^2); lambda from the peak (Eq. 19).
    const float lambda = -std::log(1.0f - theta) * 3.0f / (2.0f * std::sqrt(2.0f) * r);
    float best = 0, bestD = 0;
    for (int i = 0; i <= 2000; ++i) {
        const float d = r * float(i) / 2000.0f * 0.9999f;
        const float a = opacityAt(SphereDensity::L2, 0, theta, d, r);
        const float h = std::sqrt(r * r - d * d);
        EXPECT_NEAR(a, 1.0f - std::exp(-lambda * 2.0f * h / 3.0f * (r * r + 2.0f * d * d) / (r * r)), 3e-6f) << d;
        if (a > best) best = a, bestD = d;
    }
    EXPECT_NEAR(best, theta, 1e-5f);
    EXPECT_NEAR(bestD, r / std::sqrt(2.0f), 2e-3f * r);                         // sampling step r/2000, flat peak
    EXPECT_LT(opacityAt(SphereDensity::L2, 0, theta, 0.0f, r), theta - 0.02f);  // not at the centre
}

TEST(SphereOpacity, hollow_models_peak_at_theta_max_and_are_empty_inside) {
    for (SphereDensity model : {SphereDensity::HollowConstant, SphereDensity::HollowL2})
        for (float k : {0.3f, 0.5f, 0.8f}) {
            const float r = 1.5f, theta = 0.5f;
            float best = 0;
            for (int i = 0; i < 4000; ++i) best = std::max(best, opacityAt(model, k, theta, r * float(i) / 4000.0f, r));
            EXPECT_NEAR(best, theta, 2e-4f) << int(model) << " k=" << k;
            // Hollow constant at the centre: the chord minus the hole, 2 r (1 - k).
            if (model == SphereDensity::HollowConstant) {
                EXPECT_NEAR(opacityAt(model, k, theta, 0.0f, r),
                            1.0f - std::pow(1.0f - theta, 2.0f * (1.0f - k) / densityNormalisation(model, k)), 1e-5f);
            }
            // An eye inside the hole sees only the far shell: half the centre ray's depth.
            Ray inside{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}};
            SphereInterval s = intersectSphere(inside, glm::vec3(0.0f), r);
            SphereInterval full = intersectSphere(rayAtDistance(0.0f), glm::vec3(0.0f), r);
            EXPECT_NEAR(unitOpticalDepth(model, k, s, r), 0.5f * unitOpticalDepth(model, k, full, r), 1e-5f);
        }
}

// Staib et al. 2015, Eq. 2: L_RV = Theta ((1 - alpha_RV) L_R + alpha_RV c). alpha_rv = 1 is the
// plain volume emission (the particle colour c, no shading), 0 the Blinn-Phong surface term alone.
TEST(SphereEmission, alpha_rv_weights_the_volume_emission_as_eq2) {
    const glm::vec3 c(0.2f, 0.6f, 0.9f);
    const glm::vec3 n = glm::normalize(glm::vec3(-0.6f, -0.2f, 0.3f)), dir(0.0f, 0.0f, -1.0f);
    const glm::vec3 lightDir = glm::normalize(glm::vec3(0.5f, 0.2f, 1.0f));
    const LightingSpec light;
    const glm::vec3 surface = glm::clamp(shadeBlinnPhong(c, n, dir, lightDir, light), 0.0f, 1.0f);
    ASSERT_GT(glm::length(surface - c), 0.05f);  // the two terms differ, so the weight shows
    EXPECT_EQ(sphereEmission(c, n, dir, lightDir, light, 1.0f, 0.0f, 1.0f, glm::vec3(0.0f)), c);
    const glm::vec3 s0 = sphereEmission(c, n, dir, lightDir, light, 0.0f, 0.0f, 1.0f, glm::vec3(0.0f));
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(s0[k], surface[k]);
    const glm::vec3 mix = sphereEmission(c, n, dir, lightDir, light, 0.25f, 0.0f, 1.0f, glm::vec3(0.0f));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mix[k], 0.75f * surface[k] + 0.25f * c[k], 1e-6f);
}

// The CPU reference with alpha_rv = 1 and an opaque particle: every covered pixel is the colour.
TEST(ParticleReference, alpha_rv_one_draws_the_plain_particle_colour) {
    StyledParticles s;
    s.centerRadius = {{0, 0, 0, 0.8f}};
    s.color = {{0.2f, 0.6f, 0.9f, 1.0f}};
    s.id = {0};
    Camera cam;
    cam.eye = {0.5f, 0.3f, 3.0f};
    ParticleReferenceOptions o;
    o.spheres.alphaRv = 1.0f;
    const int W = 33;
    const FrameImages img = renderParticlesReference(s, cam, W, W, o);
    int covered = 0;
    for (std::size_t p = 0; p < std::size_t(W * W); ++p) {
        if (img.rgba[4 * p + 3] < 1.0f) continue;
        ++covered;
        for (int k = 0; k < 3; ++k) ASSERT_EQ(img.rgba[4 * p + std::size_t(k)], s.color[0][k]) << p;
    }
    EXPECT_GT(covered, 100);
}

TEST(SphereSortKey, power_distance_key_preserves_order_with_negative_values_inside) {
    const glm::vec3 eye(0.0f), fwd(0.0f, 0.0f, -1.0f);
    // Eye inside the first sphere (negative power distance), then spheres with growing power.
    struct S {
        glm::vec3 c;
        float r;
    };
    std::vector<S> spheres = {{{0, 0, -0.5f}, 2.0f}, {{0, 0, -0.1f}, 0.3f}, {{0, 0, -1.0f}, 0.1f},
                              {{0, 0, -5.0f}, 3.0f}, {{0, 0, -5.0f}, 0.5f}, {{0, 0, -100.0f}, 1.0f}};
    std::vector<float> power;
    for (const S& s : spheres) power.push_back(powerDistance(eye, s.c, s.r));
    EXPECT_LT(power[0], 0.0f);
    EXPECT_LT(power[1], 0.0f);
    for (std::size_t i = 0; i < spheres.size(); ++i)
        for (std::size_t j = 0; j < spheres.size(); ++j)
            EXPECT_EQ(power[i] < power[j], sphereSortKey(eye, false, fwd, spheres[i].c, spheres[i].r) <
                                               sphereSortKey(eye, false, fwd, spheres[j].c, spheres[j].r));
    // Random floats of both signs keep their order through the key.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1e4f, 1e4f);
    for (int i = 0; i < 10000; ++i) {
        float a = u(rng), b = u(rng);
        EXPECT_EQ(a < b, sortKeyFromFloat(a) < sortKeyFromFloat(b));
    }
}

TEST(SphereBounds, perspective_bounds_contain_the_silhouette_and_touch_it) {
    Camera cam;
    cam.eye = {0.3f, -0.2f, 4.0f};
    cam.target = {0.0f, 0.1f, 0.0f};
    cam.fovYDeg = 70.0f;
    const float aspect = 1.5f;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    for (int n = 0; n < 60; ++n) {
        const glm::vec3 c(u(rng), u(rng), u(rng));
        const float r = 0.05f + 0.3f * (u(rng) + 1.5f) / 3.0f;
        glm::vec4 rect;
        ASSERT_TRUE(projectedSphereBounds(cam, aspect, c, r, 0.0f, rect));
        // Sample the screen densely: every pixel ray that hits the sphere is inside the rect, and
        // hits occur within 1 % of each edge (tight).
        const int W = 300, H = 200;
        glm::vec4 hitRect(1e9f, 1e9f, -1e9f, -1e9f);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                if (!intersectSphere(pixelRay(cam, W, H, float(x), float(y)), c, r).hit) continue;
                const float sx = 2.0f * (x + 0.5f) / W - 1.0f, sy = 1.0f - 2.0f * (y + 0.5f) / H;
                ASSERT_GE(sx, rect.x - 1e-5f);
                ASSERT_LE(sx, rect.z + 1e-5f);
                ASSERT_GE(sy, rect.y - 1e-5f);
                ASSERT_LE(sy, rect.w + 1e-5f);
                hitRect = {std::min(hitRect.x, sx), std::min(hitRect.y, sy), std::max(hitRect.z, sx),
                           std::max(hitRect.w, sy)};
            }
        if (hitRect.x > hitRect.z) continue;  // off screen
        // Tight up to one pixel (2/W, 2/H in NDC) where the silhouette is on screen; 5 % slack for
        // grazing rays whose float intersection test misses by an ulp.
        if (rect.x > -1) {
            EXPECT_LT(hitRect.x - rect.x, 1.05f * 2.0f / W);
        }
        if (rect.z < 1) {
            EXPECT_LT(rect.z - hitRect.z, 1.05f * 2.0f / W);
        }
        if (rect.y > -1) {
            EXPECT_LT(hitRect.y - rect.y, 1.05f * 2.0f / H);
        }
        if (rect.w < 1) {
            EXPECT_LT(rect.w - hitRect.w, 1.05f * 2.0f / H);
        }
    }
    glm::vec4 rect;
    EXPECT_FALSE(projectedSphereBounds(cam, aspect, cam.eye + 5.0f * (cam.eye - cam.target), 1.0f, 0.0f, rect));
    ASSERT_TRUE(projectedSphereBounds(cam, aspect, cam.eye, 0.5f, 0.0f, rect));  // eye inside: full screen
    EXPECT_EQ(rect, glm::vec4(-1, -1, 1, 1));
}

TEST(Droplets, deterministic_by_seed_with_density_attribute) {
    ParticleSet a = generateDroplets(20000, 5), b = generateDroplets(20000, 5), c = generateDroplets(20000, 6);
    ASSERT_EQ(a.size(), 20000u);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_NE(a.positions, c.positions);
    ASSERT_NE(a.attribute("density"), nullptr);
    ASSERT_NE(a.attribute("droplet"), nullptr);
    const Attribute& rho = *a.attribute("density");
    EXPECT_GT(rho.min, 0.0f);
    EXPECT_GT(rho.max, 1.2f);  // the neck where the droplets overlap
    EXPECT_LE(rho.max, 2.0f);
    // Inside the unit cube, radius = half the mean spacing of N particles in two r = 0.2 spheres.
    EXPECT_GE(a.bounds.lo.x, 0.0f);
    EXPECT_LE(a.bounds.hi.x, 1.0f);
    const float sigma = std::cbrt(2.0f * 4.0f / 3.0f * 3.14159265f * 0.008f / 20000.0f);
    EXPECT_NEAR(a.radii[0], 0.5f * sigma, 1e-6f);
    // Roughly half in each droplet.
    std::size_t ones = std::count(a.attribute("droplet")->values.begin(), a.attribute("droplet")->values.end(), 1.0f);
    EXPECT_NEAR(double(ones) / 20000.0, 0.5, 0.02);
}

TEST(ParticleStyling, uses_style_mappings_and_data_radii_and_colors) {
    ParticleSet p;
    p.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    p.attributes = {Attribute{"t", {0.0f, 5.0f, 10.0f}}};
    p.update();
    StyleSpec style;
    style.radius.constant = 0.25f;
    style.opacity.attribute = "t";
    style.opacity.points = {{0.0f, 0.2f}, {1.0f, 0.6f}};
    StyledParticles s = styleParticles(p, style, "scene.json");
    ASSERT_EQ(s.size(), 3u);
    EXPECT_FLOAT_EQ(s.centerRadius[1].w, 0.25f);
    EXPECT_FLOAT_EQ(s.color[0].w, 0.2f);
    EXPECT_FLOAT_EQ(s.color[1].w, 0.4f);
    EXPECT_FLOAT_EQ(s.color[2].w, 0.6f);
    EXPECT_EQ(s.id[2], 2u);
    EXPECT_FLOAT_EQ(s.bounds.hi.x, 2.25f);
    // The data's own radii and colours win over constants, not over mappings.
    p.radii = {0.1f, 0.2f, 0.3f};
    p.colors = {{1, 1, 1, 1}, {1, 0, 0, 0.5f}, {0, 0, 1, 1}};
    s = styleParticles(p, style, "scene.json");
    EXPECT_FLOAT_EQ(s.centerRadius[2].w, 0.3f);
    EXPECT_EQ(glm::vec3(s.color[1]), glm::vec3(1, 0, 0));
    EXPECT_FLOAT_EQ(s.color[1].w, 0.2f);  // 0.4 x the data alpha 0.5
    style.radius.attribute = "t";
    style.radius.radiusLo = 1.0f;
    style.radius.radiusHi = 2.0f;
    s = styleParticles(p, style, "scene.json");
    EXPECT_FLOAT_EQ(s.centerRadius[1].w, 1.5f);
    style.color.attribute = "missing";
    try {
        styleParticles(p, style, "scene.json");
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("style.color.attribute"), std::string::npos) << e.what();
    }
    EXPECT_EQ(styleParticles(ParticleSet{}, StyleSpec{}, "").size(), 0u);
}

TEST(ParticleReference, orthographic_single_sphere_profile_matches_closed_form) {
    StyledParticles s;
    s.centerRadius = {{0, 0, 0, 0.8f}};
    s.color = {{1, 1, 1, 0.5f}};
    s.id = {0};
    Camera cam;
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 2.0f;
    ParticleReferenceOptions o;
    const int W = 65;
    FrameImages img = renderParticlesReference(s, cam, W, W, o);
    const std::size_t centre = std::size_t(32 * W + 32);
    EXPECT_NEAR(img.rgba[4 * centre + 3], 0.5f, 1e-6f);
    EXPECT_EQ(img.id[centre], 0u);
    EXPECT_NEAR(img.depth[centre], 3.0f - 0.8f, 1e-5f);
    for (int x = 32; x < W; ++x) {
        const float d = 2.0f * (x + 0.5f) / W - 1.0f;
        // Within 1 % of the silhouette sqrt(r^2 - d^2) cancels catastrophically in float.
        if (std::abs(d - 0.8f) < 0.008f) continue;
        const float expected = d < 0.8f ? 1.0f - std::pow(0.5f, std::sqrt(0.64f - d * d) / 0.8f) : 0.0f;
        EXPECT_NEAR(img.rgba[4 * std::size_t(32 * W + x) + 3], expected, 2e-6f) << x;
    }
    o.opaque = true;
    img = renderParticlesReference(s, cam, W, W, o);
    EXPECT_EQ(img.rgba[4 * centre + 3], 1.0f);
}

TEST(SceneSpheres, keys_are_validated) {
    nlohmann::json doc = {{"dataset", {{"generate", "droplets"}, {"particles", 1000}}},
                          {"render",
                           {{"technique", "spheres"},
                            {"transparency", "object_order"},
                            {"spheres", {{"density", "hollow_l2"}, {"inner_radius", 0.6}, {"chunks", 4}}}}}};
    Scene s = parseScene(doc, "s.json");
    EXPECT_EQ(s.dataset.generate, "droplets");
    EXPECT_EQ(s.dataset.particles, 1000);
    EXPECT_EQ(s.render.technique, RenderTechnique::Spheres);
    EXPECT_EQ(s.render.spheres.density, SphereDensity::HollowL2);
    EXPECT_FLOAT_EQ(s.render.spheres.innerRadius, 0.6f);
    EXPECT_EQ(s.render.spheres.chunks, 4);
    EXPECT_TRUE(s.render.spheres.points);  // the default billboard
    EXPECT_FALSE(s.render.spheres.earlyZStats);
    Scene q = parseScene(doc, "s.json", {"render.spheres.primitive=\"quads\"", "render.spheres.early_z_stats=true"});
    EXPECT_FALSE(q.render.spheres.points);
    EXPECT_TRUE(q.render.spheres.earlyZStats);
    auto fails = [&](const std::string& set, const std::string& text) {
        try {
            parseScene(doc, "s.json", {set});
            ADD_FAILURE() << set << ": expected InputError";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
    };
    fails("render.spheres.inner_radius=1.5", "render.spheres.inner_radius");
    fails("render.spheres.density=\"l3\"", "render.spheres.density");
    fails("render.spheres.primitive=\"triangles\"", "render.spheres.primitive");
    // The ambient transfer functions (Staib et al. 2015, Sect. 3.2): [[opacity, value], ...].
    EXPECT_TRUE(s.render.spheres.ambient.opacity.empty());  // default: the primary transfer function
    EXPECT_TRUE(s.render.spheres.ambient.emission.empty());
    Scene a = parseScene(doc, "s.json",
                         {"render.spheres.ambient_opacity=[[0, 0], [0.5, 0.2], [1, 0.4]]",
                          "render.spheres.ambient_emission=[[0, 1], [1, 0.25]]"});
    EXPECT_EQ(a.render.spheres.ambient.opacity, (std::vector<glm::vec2>{{0.0f, 0.0f}, {0.5f, 0.2f}, {1.0f, 0.4f}}));
    EXPECT_EQ(a.render.spheres.ambient.emission, (std::vector<glm::vec2>{{0.0f, 1.0f}, {1.0f, 0.25f}}));
    const glm::vec4 classified = ambientClassify(a.render.spheres.ambient, {0.8f, 0.4f, 0.2f, 0.75f});
    const glm::vec4 expected(0.8f * 0.4375f, 0.4f * 0.4375f, 0.2f * 0.4375f, 0.3f);  // e_A(0.75), Theta_A(0.75)
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(classified[k], expected[k], 1e-6f) << k;
    fails("render.spheres.ambient_opacity=[[0, 0]]", "render.spheres.ambient_opacity");
    fails("render.spheres.ambient_opacity=0.5", "render.spheres.ambient_opacity");
    fails("render.spheres.ambient_opacity=[[0, 0], [1, 1.5]]", "render.spheres.ambient_opacity[1]");
    fails("render.spheres.ambient_emission=[[0.5, 0], [0.2, 1]]", "render.spheres.ambient_emission[1]");
    fails("render.spheres.ambient_emission=[[0, 0], \"x\"]", "render.spheres.ambient_emission[1]");
    fails(
        "render.spheres.ambient_emission=[[0,0],[0,0],[0,0],[0,0],[0,0],[0,0],[0,0],[0,0],[0,0],[0,0],[0,0],"
        "[0,0],[0,0],[0,0],[0,0],[0,0],[1,0]]",
        "render.spheres.ambient_emission");
    fails("dataset.lines=5", "dataset.lines");
}

}  // namespace
}  // namespace tc
