// Particles in the Embree ray tracer (rt/raytraced_particles.h) against the CPU particle reference
// (core/particle_reference.h): opaque first hit, the emission-absorption interior of every
// density model, the multi-pass continuation, the eye inside a sphere, and thread independence.
#include "rt/raytraced_particles.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/error.h"
#include "core/particle_reference.h"

namespace tc {
namespace {

// `count` disjoint spheres (the reference is exact for those) in [-0.8, 0.8]^3 with radii
// 0.05..0.2, random linear colours and opacities in [alphaLo, alphaHi].
StyledParticles randomSpheres(unsigned seed, int count, float alphaLo, float alphaHi) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-0.8f, 0.8f), rad(0.05f, 0.2f), col(0.05f, 1.0f), alpha(alphaLo, alphaHi);
    StyledParticles s;
    while (int(s.size()) < count) {
        const glm::vec4 c(pos(rng), pos(rng), pos(rng), rad(rng));
        const bool overlaps = std::any_of(s.centerRadius.begin(), s.centerRadius.end(), [&](const glm::vec4& o) {
            return glm::distance(glm::vec3(c), glm::vec3(o)) < c.w + o.w;
        });
        if (overlaps) continue;
        s.centerRadius.push_back(c);
        s.color.push_back({col(rng), col(rng), col(rng), alpha(rng)});
        s.id.push_back(std::uint32_t(1000 + s.size()));
        s.bounds.extend(glm::vec3(c), c.w);
        s.maxRadius = std::max(s.maxRadius, c.w);
    }
    return s;
}

Scene particleScene(Transparency transparency, SphereDensity density, float cutoff = 1.0f) {
    Scene s;
    s.render.technique = RenderTechnique::Raytraced;
    s.render.transparency = transparency;
    s.render.raytracedAlphaCutoff = cutoff;
    s.render.spheres.density = density;
    s.render.spheres.innerRadius = 0.6f;
    s.render.spheres.alphaRv = 0.7f;
    s.output.aovDepth = s.output.aovNormal = s.output.aovId = true;  // every AOV, to compare
    return s;
}

FrameImages raytrace(const Scene& scene, const StyledParticles& p, const Camera& cam, int w, int h) {
    auto r = rt::RaytracedParticles::create(scene, p);
    FrameImages img;
    tc::CpuStageTimer timer;
    r->render(cam, w, h, img, timer);
    return img;
}

FrameImages reference(const Scene& scene, const StyledParticles& p, const Camera& cam, int w, int h) {
    ParticleReferenceOptions o;
    o.spheres = scene.render.spheres;
    o.lighting = scene.lighting;
    o.opaque = scene.render.transparency == Transparency::Opaque;
    return renderParticlesReference(p, cam, w, h, o);
}

Camera cameraAt(glm::vec3 eye, Projection projection = Projection::Perspective) {
    Camera cam;
    cam.eye = eye;
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 45.0f;
    cam.projection = projection;
    cam.orthoHeight = 2.2f;
    return cam;
}

// Per pixel: the same first sphere (id), depth and normal, and RGBA within `tol`. Pixels where one
// side sees a sphere the other misses, or another first sphere, are counted, not failed: Embree's
// sphere test and core/sphere_glyph.h decide rays grazing a silhouette with other float
// operations (there the interval, and so the opacity, is ~0 anyway).
struct Diff {
    int covered = 0, mismatched = 0;
    float maxRgba = 0;
};

Diff compare(const FrameImages& rt, const FrameImages& ref) {
    Diff d;
    for (std::size_t i = 0; i < ref.pixelCount(); ++i) {
        d.covered += ref.id[i] != kBackgroundId;
        if (rt.id[i] != ref.id[i]) {
            ++d.mismatched;
            continue;
        }
        for (int c = 0; c < 4; ++c)
            d.maxRgba =
                std::max(d.maxRgba, std::abs(rt.rgba[4 * i + std::size_t(c)] - ref.rgba[4 * i + std::size_t(c)]));
        if (ref.id[i] == kBackgroundId) continue;
        EXPECT_NEAR(rt.depth[i], ref.depth[i], 1e-5f * std::max(1.0f, ref.depth[i])) << i;
        glm::vec3 n1(rt.normal[3 * i], rt.normal[3 * i + 1], rt.normal[3 * i + 2]);
        glm::vec3 n2(ref.normal[3 * i], ref.normal[3 * i + 1], ref.normal[3 * i + 2]);
        // (Not unit for a sphere around the eye: (eye - centre) / radius, as the reference.)
        EXPECT_LT(glm::distance(n1, n2), 1e-4f) << i;
    }
    return d;
}

TEST(RaytracedParticles, opaque_and_every_density_model_equal_the_cpu_particle_reference) {
    const int w = 64, h = 48;
    int covered = 0, mismatched = 0;
    float maxRgba = 0;
    StyledParticles p = randomSpheres(5u, 60, 0.2f, 0.9f);
    for (Projection projection : {Projection::Perspective, Projection::Orthographic}) {
        Camera cam = cameraAt({0.5f, 0.7f, 2.6f}, projection);
        std::vector<Scene> scenes = {particleScene(Transparency::Opaque, SphereDensity::Constant)};
        for (SphereDensity d :
             {SphereDensity::Constant, SphereDensity::L2, SphereDensity::HollowConstant, SphereDensity::HollowL2})
            scenes.push_back(particleScene(Transparency::ObjectOrder, d));
        for (const Scene& scene : scenes) {
            Diff d = compare(raytrace(scene, p, cam, w, h), reference(scene, p, cam, w, h));
            covered += d.covered;
            mismatched += d.mismatched;
            maxRgba = std::max(maxRgba, d.maxRgba);
        }
    }
    EXPECT_GT(covered, 10 * w * h / 4);  // the spheres cover a good part of every image
    // The same intervals and formulas: float noise only. Silhouette pixels may differ in coverage.
    EXPECT_LT(maxRgba, 1e-4f);
    EXPECT_LE(mismatched, covered / 200) << mismatched << " of " << covered;
}

TEST(RaytracedParticles, exact_compositing_continues_past_one_traversal_and_the_cutoff_stops_early) {
    // 70 spheres on the view axis: more than one Embree traversal collects (48).
    StyledParticles p;
    for (int k = 0; k < 70; ++k) {
        const glm::vec4 c(0.002f * float(k % 5), 0.0f, -1.4f + 0.04f * float(k), 0.3f * 0.06f + 0.001f * float(k % 3));
        p.centerRadius.push_back(c);
        p.color.push_back({0.2f + 0.01f * float(k), 0.5f, 0.9f - 0.01f * float(k), 0.08f});
        p.id.push_back(std::uint32_t(k));
        p.bounds.extend(glm::vec3(c), c.w);
        p.maxRadius = std::max(p.maxRadius, c.w);
    }
    Camera cam = cameraAt({0.0f, 0.0f, 3.0f}, Projection::Orthographic);
    cam.orthoHeight = 0.1f;
    const int w = 16, h = 12;
    Scene exact = particleScene(Transparency::ObjectOrder, SphereDensity::Constant);
    FrameImages ref = reference(exact, p, cam, w, h);
    const std::size_t centre = std::size_t(h / 2) * w + w / 2;
    // Sanity of the scene: the centre ray crosses all 70 (through the centres: 1 - 0.92^70 = 0.997).
    EXPECT_GT(ref.rgba[4 * centre + 3], 0.95f);
    Diff d = compare(raytrace(exact, p, cam, w, h), ref);
    EXPECT_EQ(d.mismatched, 0);
    EXPECT_LT(d.maxRgba, 1e-4f);

    const float cutoff = 0.8f;
    FrameImages cut = raytrace(particleScene(Transparency::ObjectOrder, SphereDensity::Constant, cutoff), p, cam, w, h);
    for (std::size_t i = 0; i < ref.pixelCount(); ++i)
        for (int c = 0; c < 4; ++c)
            EXPECT_LE(std::abs(cut.rgba[4 * i + std::size_t(c)] - ref.rgba[4 * i + std::size_t(c)]),
                      1.0f - cutoff + 1e-5f);
    EXPECT_LT(cut.rgba[4 * centre + 3], ref.rgba[4 * centre + 3]);  // it did stop
    EXPECT_GE(cut.rgba[4 * centre + 3], cutoff);
}

TEST(RaytracedParticles, eye_inside_a_sphere_composites_it_first_like_the_reference) {
    StyledParticles p = randomSpheres(6u, 30, 0.3f, 0.8f);
    // A large sphere around the eye, disjoint from the others (they lie within 0.8 + 0.2 of 0).
    const glm::vec4 big(0.0f, 0.0f, 3.0f, 0.9f);
    p.centerRadius.push_back(big);
    p.color.push_back({0.9f, 0.2f, 0.2f, 0.5f});
    p.id.push_back(7u);
    Camera cam = cameraAt({0.0f, 0.1f, 3.2f});
    const int w = 40, h = 30;
    Scene scene = particleScene(Transparency::ObjectOrder, SphereDensity::L2);
    FrameImages ref = reference(scene, p, cam, w, h);
    Diff d = compare(raytrace(scene, p, cam, w, h), ref);
    EXPECT_EQ(d.covered, w * h);  // every ray starts inside the big sphere
    EXPECT_EQ(ref.id[0], 7u);
    EXPECT_LE(d.mismatched, d.covered / 100);
    EXPECT_LT(d.maxRgba, 1e-4f);
}

TEST(RaytracedParticles, images_are_identical_with_one_and_two_threads_and_every_traversal) {
    StyledParticles p = randomSpheres(7u, 40, 0.3f, 0.9f);
    Camera cam = cameraAt({0.3f, 0.4f, 2.5f});
    for (Transparency t : {Transparency::Opaque, Transparency::ObjectOrder}) {
        Scene scene = particleScene(t, SphereDensity::HollowL2, 0.95f);
        std::vector<FrameImages> images;
        for (int threads : {1, 2}) {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
            images.push_back(raytrace(scene, p, cam, 37, 29));
        }
        auto r = rt::RaytracedParticles::create(scene, p);
        for (rt::Traversal traversal : {rt::Traversal::Single, rt::Traversal::Stream}) {
            r->setTraversal(traversal);
            FrameImages img;
            tc::CpuStageTimer timer;
            r->render(cam, 37, 29, img, timer);
            images.push_back(std::move(img));
        }
        for (std::size_t k = 1; k < images.size(); ++k) {
            EXPECT_EQ(images[k].rgba, images[0].rgba) << k;
            EXPECT_EQ(images[k].depth, images[0].depth) << k;
            EXPECT_EQ(images[k].id, images[0].id) << k;
        }
    }
}

TEST(RaytracedParticles, writes_only_the_aovs_the_output_asks_for_and_the_same_colour) {
    const StyledParticles p = randomSpheres(11u, 40, 0.3f, 0.9f);
    const Camera cam = cameraAt({0.4f, 0.3f, 2.2f});
    for (Transparency t : {Transparency::Opaque, Transparency::ObjectOrder}) {
        const Scene all = particleScene(t, SphereDensity::L2, 0.99f);
        const FrameImages full = raytrace(all, p, cam, 40, 30);
        ASSERT_EQ(full.id.size(), full.pixelCount());
        FrameImages reused = full;  // a target that held every AOV in the previous frame
        for (const KeptAovs keep : {KeptAovs{false, false, false}, KeptAovs{true, false, true}}) {
            Scene some = all;
            some.output.aovDepth = keep.depth;
            some.output.aovNormal = keep.normal;
            some.output.aovId = keep.id;
            auto r = rt::RaytracedParticles::create(some, p);
            tc::CpuStageTimer timer;
            r->render(cam, 40, 30, reused, timer);
            EXPECT_EQ(reused.rgba, full.rgba);
            EXPECT_EQ(reused.depth, keep.depth ? full.depth : std::vector<float>{});
            EXPECT_EQ(reused.normal, keep.normal ? full.normal : std::vector<float>{});
            EXPECT_EQ(reused.id, keep.id ? full.id : std::vector<std::uint32_t>{});
        }
    }
}

TEST(RaytracedParticles, rejects_opacity_optimization) {
    StyledParticles p = randomSpheres(8u, 3, 0.5f, 0.5f);
    Scene scene = particleScene(Transparency::ObjectOrder, SphereDensity::Constant);
    scene.render.transparency = Transparency::OpacityOptimization;
    EXPECT_THROW(rt::RaytracedParticles::create(scene, p), InputError);
}

}  // namespace
}  // namespace tc
