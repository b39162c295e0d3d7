// The lighting of voxel-based line ray casting as Kanzler, Rautenhaus & Westermann 2019 compute it
// (shaders/vrc_lighting.glsl): density-ray and precomputed spherical AO on the Eq. 1 density
// (Sec. 5.3), soft shadows by a cone through the Eq. 1 pyramid and hard shadows against the tubes
// (Sec. 5.2). Invariants and CPU ground truth:
//   - AO: a tube inside a dense bundle is darker than an isolated tube (both AO methods);
//   - the GPU's per-voxel precomputed AO equals the CPU's density rays at the voxel centres;
//   - shadows: a tube's shadow lies on the plane of tubes behind it along the light, nowhere else;
//   - hard shadows against the tubes agree with a CPU shadow ray against every rounded cone.
#include "core/vrc_lighting.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/camera.h"
#include "core/rounded_cone.h"
#include "core/scene.h"
#include "core/shading.h"
#include "core/technique.h"
#include "core/vrc_model.h"
#include "gl/gl_util.h"
#include "gl/gpu_timer.h"
#include "gl/objects.h"
#include "gl/techniques.h"
#include "gl/vrc_renderer.h"
#include "gl_fixture.h"
#include "test_scenes.h"

namespace tc::test {
namespace {

// Opaque, exact end points (no quantization).
Scene exactVrcScene(int w, int h, int resolution) {
    Scene scene = vrcScene(w, h, resolution, Transparency::Opaque);
    scene.render.vrc.quantization = 0;
    return scene;
}

FrameImages render(const Scene& scene, const StyledLines& lines, const Camera& cam) {
    std::unique_ptr<tc::Technique> t = gl::createTechnique(scene, lines);
    gl::StageTimer timer;
    FrameImages out;
    t->render(tc::FrameSetup{0, cam, scene.image.width, scene.image.height}, out, timer);
    timer.collect();
    return out;
}

Camera topCamera(float orthoHeight) {
    Camera cam;
    cam.eye = {0.0f, 0.0f, 2.0f};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = orthoHeight;
    return cam;
}

// World x, y of pixel (x, y) (y = 0 the top row) in topCamera's view.
glm::vec2 worldXY(const FrameImages& f, float orthoHeight, int x, int y) {
    return {(float(x) + 0.5f - 0.5f * float(f.width)) / float(f.height) * orthoHeight,
            (0.5f * float(f.height) - float(y) - 0.5f) / float(f.height) * orthoHeight};
}

std::size_t at(const FrameImages& f, int x, int y) {
    return std::size_t(y) * std::size_t(f.width) + std::size_t(x);
}

// A bundle of 5 x 5 parallel tubes along y (spacing 2 radii apart, centred on x = -0.5) and one
// isolated tube at x = +0.5, all of radius 0.02: the isolated tube is 0.7 (28 voxels at resolution
// 64) from the bundle, beyond the 15-voxel radius of influence. Polyline 22 is the middle tube of
// the bundle's top row (z = +0.16, the row the camera sees), 25 the isolated tube.
StyledLines bundleAndIsolatedTube() {
    std::vector<TestPolyline> p;
    const glm::vec4 grey(0.8f, 0.8f, 0.8f, 1.0f);
    for (int i = 0; i < 5; ++i)
        for (int k = 0; k < 5; ++k) {
            const float x = -0.5f + 0.08f * float(k - 2), z = 0.08f * float(i - 2);
            p.push_back({{{x, -0.8f, z}, 0.02f, grey}, {{x, 0.8f, z}, 0.02f, grey}});
        }
    p.push_back({{{0.5f, -0.8f, 0.0f}, 0.02f, grey}, {{0.5f, 0.8f, 0.0f}, 0.02f, grey}});
    return makeStyledLines(p);
}

// Mean AOV of the pixels showing polyline `id` in the middle rows.
float meanAo(const FrameImages& f, std::uint32_t id) {
    double sum = 0;
    int n = 0;
    for (int y = f.height / 4; y < 3 * f.height / 4; ++y)
        for (int x = 0; x < f.width; ++x)
            if (f.id[at(f, x, y)] == id) {
                sum += f.ao[at(f, x, y)];
                ++n;
            }
    EXPECT_GT(n, 20) << "polyline " << id << " covers too few pixels";
    return n > 0 ? float(sum / n) : 0.0f;
}

void expectBundleDarkerThanIsolated(VrcSpec::Ao::Method method, const char* name, float minGap) {
    const StyledLines lines = bundleAndIsolatedTube();
    const float orthoHeight = 1.2f;
    Scene scene = exactVrcScene(160, 96, 64);
    scene.render.ao.enabled = true;
    scene.render.vrc.ao.method = method;
    const FrameImages f = render(scene, lines, topCamera(orthoHeight));
    ASSERT_EQ(f.ao.size(), f.id.size());
    const float bundle = meanAo(f, 22), isolated = meanAo(f, 25);
    std::printf("vrc %s AO: bundle tube %.3f, isolated tube %.3f\n", name, bundle, isolated);
    EXPECT_LT(bundle, isolated - minGap);
}

TEST_F(GlTest, vrc_density_ray_ao_is_lower_inside_a_bundle_than_on_an_isolated_tube) {
    // The own tube is excluded from the reads (shaders/vrc_lighting.glsl), so the isolated tube is
    // unoccluded and the bundle's top tube has its neighbours in half of its hemisphere.
    expectBundleDarkerThanIsolated(VrcSpec::Ao::Method::DensityRays, "density_rays", 0.15f);
}

TEST_F(GlTest, vrc_precomputed_ao_is_lower_inside_a_bundle_than_on_an_isolated_tube) {
    expectBundleDarkerThanIsolated(VrcSpec::Ao::Method::Precomputed, "precomputed", 0.15f);
}

TEST_F(GlTest, vrc_density_ray_ao_of_an_isolated_tube_is_one) {
    // Nothing but its own line within 15 voxels: with its own deposit taken out of every read the
    // hemisphere rays see empty space (R16F rounding of the deposit aside).
    const StyledLines lines = bundleAndIsolatedTube();
    Scene scene = exactVrcScene(160, 96, 64);
    scene.render.ao.enabled = true;
    scene.render.vrc.ao.method = VrcSpec::Ao::Method::DensityRays;
    const FrameImages f = render(scene, lines, topCamera(1.2f));
    EXPECT_GT(meanAo(f, 25), 0.97f);
}

TEST_F(GlTest, vrc_precomputed_ao_equals_cpu_sphere_density_rays_at_voxel_centres) {
    RandomSceneOptions o;
    o.polylines = 30;
    o.radiusMin = 0.01f;
    o.radiusRatio = 2.0f;
    const StyledLines lines = randomLineScene(7, o);
    VrcBuildOptions options;
    options.resolution = 32;
    options.quantization = 0;
    options.lod = true;
    const VrcModel model = buildVrcModel(lines, options);
    const gl::Buffer header = gl::makeBuffer(model.voxels.size() * sizeof(VrcVoxel), model.voxels.data());
    const gl::VrcDensityTexture density = gl::uploadVrcDensity(model);
    const int rays = 40;
    const float radius = 15.0f;
    const gl::Texture ao = gl::precomputeVrcSphereAo(model, header, density, rays, radius);
    std::vector<float> gpu(model.voxelCount());
    glGetTextureImage(ao.id(), 0, GL_RED, GL_FLOAT, GLsizei(gpu.size() * sizeof(float)), gpu.data());
    float maxDiff = 0, minAo = 1;
    std::size_t computed = 0;
    for (std::size_t i = 0; i < model.voxelCount(); ++i) {
        if (!(model.voxels[i].count & kNeighbourhoodBit)) {
            EXPECT_EQ(gpu[i], 1.0f);
            continue;
        }
        const float cpu = vrcSphereAmbientOcclusion(model.lod[0], glm::vec3(model.coords(i)) + 0.5f, rays, radius);
        maxDiff = std::max(maxDiff, std::abs(cpu - gpu[i]));
        minAo = std::min(minAo, cpu);
        ++computed;
    }
    std::printf("vrc precomputed AO: %zu voxels, max |gpu - cpu| %.5f, min AO %.3f\n", computed, maxDiff, minAo);
    EXPECT_GT(computed, model.voxelCount() / 20);
    EXPECT_LT(minAo, 0.7f);  // the scene occludes: the comparison is not of constants
    // R16F holds AO to 2^-11; the GPU's trilinear weights and sums round differently from the CPU's.
    EXPECT_LT(maxDiff, 0.01f);
}

// A plane of 12 tubes along x at z = 0 (y = -0.55 .. 0.55) and one occluder tube along y at x = 0,
// z = `height` above it. With the light toward (0.6, 0, 0.8) the occluder's shadow falls on the
// plane around x = -0.75 height.
StyledLines planeAndOccluder(float height) {
    std::vector<TestPolyline> p;
    const glm::vec4 grey(0.8f, 0.8f, 0.8f, 1.0f);
    for (int k = 0; k < 12; ++k) {
        const float y = -0.55f + 0.1f * float(k);
        p.push_back({{{-0.8f, y, 0.0f}, 0.03f, grey}, {{0.8f, y, 0.0f}, 0.03f, grey}});
    }
    p.push_back({{{0.0f, -0.7f, height}, 0.03f, grey}, {{0.0f, 0.7f, height}, 0.03f, grey}});
    return makeStyledLines(p);
}

// Summed red of the plane's pixels (not the occluder, id 12) with world x in [x0, x1].
float planeRed(const FrameImages& f, float orthoHeight, float x0, float x1) {
    float sum = 0;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            const glm::vec2 w = worldXY(f, orthoHeight, x, y);
            const std::uint32_t id = f.id[at(f, x, y)];
            if (w.x >= x0 && w.x <= x1 && id < 12u) sum += f.rgba[4 * at(f, x, y)];
        }
    return sum;
}

struct ShadowBands {
    float shadow, mirror, elsewhere;  // shadowed / lit red: the shadow's band, its mirror, the rest
};

ShadowBands shadowBands(VrcSpec::ShadowMode mode, float height) {
    const StyledLines lines = planeAndOccluder(height);
    const float orthoHeight = 1.4f;
    const Camera cam = topCamera(orthoHeight);
    Scene scene = exactVrcScene(192, 160, 32);
    scene.lighting.direction = {0.6f, 0.0f, 0.8f};  // camera space = world space for topCamera
    const FrameImages lit = render(scene, lines, cam);
    scene.render.vrc.shadows = true;
    scene.render.vrc.shadowMode = mode;
    const FrameImages shadowed = render(scene, lines, cam);
    // The shadow of the occluder's axis on the plane tubes' upper half (z ~ 0.015).
    const float xs = -0.75f * (height - 0.015f);
    auto ratio = [&](float x0, float x1) {
        const float l = planeRed(lit, orthoHeight, x0, x1);
        EXPECT_GT(l, 10.0f);
        return planeRed(shadowed, orthoHeight, x0, x1) / l;
    };
    ShadowBands b{ratio(xs - 0.025f, xs + 0.025f), ratio(-xs - 0.025f, -xs + 0.025f), ratio(0.4f, 0.75f)};
    std::printf("vrc shadows (mode %d, occluder %.2f above): shadow band %.3f, mirror band %.3f, elsewhere %.3f\n",
                int(mode), height, b.shadow, b.mirror, b.elsewhere);
    return b;
}

TEST_F(GlTest, vrc_hard_tube_shadow_falls_on_the_plane_behind_the_tube_along_the_light_only) {
    const ShadowBands b = shadowBands(VrcSpec::ShadowMode::HardTubes, 0.2f);
    // The band is one tube diameter wide around the shadow's axis: the diffuse and specular light
    // of its pixels is gone (ambient stays).
    EXPECT_LT(b.shadow, 0.6f);
    EXPECT_GT(b.mirror, 0.999f);  // nothing toward the light, no self-shadowing
    EXPECT_GT(b.elsewhere, 0.999f);
}

TEST_F(GlTest, vrc_density_cone_shadow_falls_on_the_plane_behind_the_tube_along_the_light_only) {
    // The occluder 0.1 above the plane (~1.5 voxels of gap at resolution 32). The cone's diameter
    // is its distance in voxels, so the shadow is soft and shallow; and a cone from the mirror band
    // passes the occluder within its footprint, which darkens that band too, less than the shadow
    // (measured: shadow band 0.83, mirror 0.91, far 0.99; at 0.2 above 0.91, 0.93, 0.97).
    const ShadowBands b = shadowBands(VrcSpec::ShadowMode::DensityCone, 0.1f);
    EXPECT_LT(b.shadow, b.mirror - 0.04f);
    EXPECT_LT(b.shadow, b.elsewhere - 0.1f);
    EXPECT_GT(b.elsewhere, 0.97f);  // far from the occluder: the plane's own tubes barely (own line excluded)
}

// CPU: the nearest rounded-cone surface along `ray` among `cones`.
std::optional<std::pair<SurfaceHit, std::size_t>> nearest(const std::vector<RoundedCone>& cones, const Ray& ray) {
    std::optional<std::pair<SurfaceHit, std::size_t>> best;
    for (std::size_t i = 0; i < cones.size(); ++i) {
        const std::optional<SurfaceHit> h = nearestPositiveHit(intersectRoundedCone(ray, cones[i]));
        if (h && (!best || h->t < best->first.t)) best = std::make_pair(*h, i);
    }
    return best;
}

bool blocked(const std::vector<RoundedCone>& cones, const Ray& ray) {
    for (const RoundedCone& c : cones) {
        const ConeInterval iv = intersectRoundedCone(ray, c);
        if (iv.hit && iv.tOut > 0.0f) return true;
    }
    return false;
}

TEST_F(GlTest, vrc_hard_tube_shadows_agree_with_a_cpu_shadow_ray_against_every_tube) {
    RandomSceneOptions o;
    o.polylines = 12;
    o.radiusMin = 0.03f;
    o.radiusRatio = 2.0f;
    const std::uint32_t seed = 11;
    const StyledLines lines = randomLineScene(seed, o);
    // The CPU's tubes: the voxel model's own pieces (not the copies) as the renderer builds them
    // (exact ends; a polyline bending inside a voxel is that voxel's chord), each a rounded cone.
    VrcBuildOptions options;
    options.resolution = 24;
    options.quantization = 0;
    options.lod = false;
    const VrcModel model = buildVrcModel(lines, options);
    std::vector<RoundedCone> cones;
    std::vector<std::uint32_t> coneLine;
    for (std::size_t i = 0; i < model.pieceCount(); ++i) {
        const VrcPiece piece = model.piece(i);
        cones.push_back({piece.a, piece.ra, piece.b, piece.rb});
        coneLine.push_back(piece.line);
    }
    Camera cam;
    cam.eye = {0.6f, 0.8f, 2.6f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 45.0f;
    const int w = 96, h = 80;
    Scene scene = exactVrcScene(w, h, 24);
    scene.lighting.direction = {0.5f, 0.7f, 0.5f};
    const FrameImages lit = render(scene, lines, cam);
    scene.render.vrc.shadows = true;
    scene.render.vrc.shadowMode = VrcSpec::ShadowMode::HardTubes;
    const FrameImages shadowed = render(scene, lines, cam);
    const glm::vec3 light = lightDirectionWorld(scene.lighting, cam);

    int compared = 0, agree = 0, cpuShadowed = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Ray ray = pixelRay(cam, w, h, float(x), float(y));
            const auto hit = nearest(cones, ray);
            if (!hit || lit.id[at(lit, x, y)] != coneLine[hit->second]) continue;
            const glm::vec3 n = hit->first.normal;
            if (glm::dot(n, light) < 0.1f) continue;  // little diffuse light to lose
            const glm::vec3 p = ray.origin + hit->first.t * ray.dir;
            // Shadow rays from two points 1e-3 apart on the tangent plane: where they disagree the
            // ray grazes a tube and float noise decides.
            const glm::vec3 side = glm::normalize(glm::cross(n, light + glm::vec3(1e-3f)));
            const bool b0 = blocked(cones, {p + 1e-4f * n, light});
            const bool b1 = blocked(cones, {p + 1e-4f * n + 1e-3f * side, light});
            const bool b2 = blocked(cones, {p + 1e-4f * n - 1e-3f * side, light});
            if (b0 != b1 || b0 != b2) continue;
            // Shadowed pixels lose diffuse and specular light (all channels: some tubes have no red).
            float litSum = 0, shadowedSum = 0;
            for (int c = 0; c < 3; ++c) {
                litSum += lit.rgba[4 * at(lit, x, y) + std::size_t(c)];
                shadowedSum += shadowed.rgba[4 * at(lit, x, y) + std::size_t(c)];
            }
            const bool gpu = shadowedSum < litSum - 1e-4f;
            if (gpu != b0)
                std::printf("  disagree at (%d, %d): gpu %d cpu %d, n.l %.3f, lit %.4f shadowed %.4f\n", x, y, int(gpu),
                            int(b0), glm::dot(n, light), litSum, shadowedSum);
            ++compared;
            agree += gpu == b0;
            cpuShadowed += b0;
        }
    std::printf("vrc hard tube shadows: %d pixels compared, %d agree, %d shadowed on the CPU\n", compared, agree,
                cpuShadowed);
    EXPECT_GT(compared, 500);
    EXPECT_GT(cpuShadowed, 50);  // the scene has shadows to agree on
    EXPECT_GE(agree, compared - compared / 200);
}

}  // namespace
}  // namespace tc::test
