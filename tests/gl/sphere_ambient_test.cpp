// GPU voxelization of sphere glyphs for AO and ambient light (gl/sphere_ambient.h): the deposited
// coverage against the spheres' analytic volume within the 3x3x3 sampling bound, exact
// containment, sub-voxel spheres adding their volume fractions, a straddling sphere's split, the
// CPU twin's volume, the ambient transfer functions, and the cone traced AO darkening a sphere
// among others.
#include "gl/sphere_ambient.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/scene.h"
#include "core/styled_particles.h"
#include "gl/gpu_timer.h"
#include "gl/sphere_renderer.h"
#include "gl_fixture.h"
#include "rt/particle_ambient.h"

namespace tc::test {
namespace {

StyledParticles spheres(const std::vector<glm::vec4>& cr) {
    StyledParticles p;
    for (const glm::vec4& s : cr) {
        p.centerRadius.push_back(s);
        p.color.push_back(glm::vec4(1.0f));
        p.id.push_back(std::uint32_t(p.id.size()));
        p.bounds.extend(glm::vec3(s), s.w);
        p.maxRadius = std::max(p.maxRadius, s.w);
    }
    return p;
}

// The 3x3x3 rule is exact on sub-cells wholly inside or outside a sphere; a sub-cell the surface
// cuts contributes its sample (0 or 1) instead of its covered fraction, an error below one
// sub-cell (1/27 voxel). The bound is the number of cut sub-cells / 27, in voxels, over partially
// covered voxels (fully covered and disjoint voxels are exact by construction).
double samplingBound(const glm::vec4& s, glm::vec3 origin, float voxel) {
    const glm::vec3 c = (glm::vec3(s) - origin) / voxel;
    const float r = s.w / voxel;
    double bound = 0;
    auto cut = [&](glm::vec3 lo, glm::vec3 hi) {
        glm::vec3 n = glm::clamp(c, lo, hi) - c;
        glm::vec3 f = glm::max(glm::abs(lo - c), glm::abs(hi - c));
        return glm::dot(n, n) < r * r && glm::dot(f, f) > r * r;
    };
    for (int z = int(std::floor(c.z - r)); z <= int(std::floor(c.z + r)); ++z)
        for (int y = int(std::floor(c.y - r)); y <= int(std::floor(c.y + r)); ++y)
            for (int x = int(std::floor(c.x - r)); x <= int(std::floor(c.x + r)); ++x) {
                glm::vec3 lo(x, y, z);
                if (!cut(lo, lo + 1.0f)) continue;
                for (int k = 0; k < 27; ++k) {
                    glm::vec3 sl = lo + glm::vec3(k % 3, (k / 3) % 3, k / 9) / 3.0f;
                    bound += cut(sl, sl + 1.0f / 3.0f) ? 1.0 / 27.0 : 0.0;
                }
            }
    return bound;
}

class SphereAmbientTest : public GlTest {};

TEST_F(SphereAmbientTest, deposited_weight_equals_sphere_volumes_within_sampling_bound) {
    std::mt19937 rng(9);
    auto u = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) / 16777216.0f; };
    std::vector<glm::vec4> cr;
    for (int i = 0; i < 60; ++i) cr.push_back(glm::vec4(u(0, 1), u(0, 1), u(0, 1), u(0.01f, 0.08f)));
    StyledParticles p = spheres(cr);
    AoSpec spec;
    spec.enabled = true;
    spec.resolution = 96;
    gl::SphereAmbient ambient = gl::SphereAmbient::create(spec, /*cached=*/false);
    ambient.voxelize(p, p.bounds);
    std::vector<glm::vec4> v = ambient.readLevel0();
    double total = 0;
    for (const glm::vec4& x : v) total += x.w;
    const double voxel3 = double(ambient.voxelSize()) * ambient.voxelSize() * ambient.voxelSize();
    double expected = 0, bound = 0;
    for (const glm::vec4& s : cr) {
        expected += 4.0 / 3.0 * M_PI * double(s.w) * s.w * s.w / voxel3;
        bound += samplingBound(s, ambient.origin(), ambient.voxelSize());
    }
    std::printf("[ info ] deposited %.2f voxels, analytic %.2f, bound %.2f\n", total, expected, bound);
    EXPECT_LE(std::abs(total - expected), bound);
    EXPECT_LT(bound, 0.5 * expected);  // the bound is not vacuous
    // White spheres: rgb equals alpha everywhere (premultiplied colour).
    for (const glm::vec4& x : v) ASSERT_NEAR(x.x, x.w, 1e-5f);
}

TEST_F(SphereAmbientTest, a_sphere_containing_a_voxel_gives_full_coverage) {
    StyledParticles p = spheres({{0.5f, 0.5f, 0.5f, 0.5f}});
    AoSpec spec;
    spec.resolution = 16;  // voxel 1/16; the sphere contains the central voxels
    gl::SphereAmbient ambient = gl::SphereAmbient::create(spec, /*cached=*/false);
    ambient.voxelize(p, p.bounds);
    std::vector<glm::vec4> v = ambient.readLevel0();
    glm::ivec3 n = ambient.size();
    ASSERT_EQ(n, glm::ivec3(16));
    auto at = [&](int x, int y, int z) { return v[std::size_t(x + n.x * (y + n.y * z))].w; };
    EXPECT_EQ(at(8, 8, 8), 1.0f);
    // Every voxel the sphere contains reads exactly 1, every voxel it misses 0, the rest between.
    int inside = 0, cut = 0;
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                const glm::vec3 lo = glm::vec3(x, y, z) / 16.0f, hi = lo + 1.0f / 16.0f, c(0.5f);
                const glm::vec3 nearest = glm::clamp(c, lo, hi) - c;
                const glm::vec3 farthest = glm::max(glm::abs(lo - c), glm::abs(hi - c));
                const float w = at(x, y, z);
                if (glm::length(farthest) < 0.499f) {
                    ++inside;
                    ASSERT_EQ(w, 1.0f) << x << " " << y << " " << z;
                } else if (glm::length(nearest) > 0.501f) {
                    ASSERT_EQ(w, 0.0f) << x << " " << y << " " << z;
                } else {
                    ++cut;
                    ASSERT_GE(w, 0.0f);
                    ASSERT_LE(w, 1.0f);
                }
            }
    EXPECT_GT(inside, 1000);
    EXPECT_GT(cut, 100);
}

// Staib et al. 2015, Sect. 5.1: a voxel that contains a whole sphere gets the fraction of its
// space the sphere fills. A cloud of 400 spheres with radii 0.016..0.08 voxel inside one voxel
// (each far below the 1/3-voxel spacing of the 3x3x3 sub-samples, which alone would catch almost
// none of them) gives that voxel sum(4/3 pi r^3 / voxel^3 x opacity) in alpha and the same times
// the colour in rgb; the tolerance is the fixed-point rounding, half a unit of 1 / (27 x 2^16)
// voxel per sphere, plus float rounding. Every other voxel stays 0. The CPU twin
// (rt::SphereVolume) deposits the same.
TEST_F(SphereAmbientTest, spheres_far_smaller_than_a_voxel_add_their_volume_fractions) {
    std::mt19937 rng(4);
    auto u = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) / 16777216.0f; };
    const float voxel = 0.125f;  // bounds [0, 1]^3 at resolution 8
    const glm::ivec3 target(3, 4, 5);
    StyledParticles p;
    double alpha = 0, red = 0;
    for (int i = 0; i < 400; ++i) {
        const float r = voxel * u(0.016f, 0.08f);
        const glm::vec3 c = (glm::vec3(target) + glm::vec3(u(0.1f, 0.9f), u(0.1f, 0.9f), u(0.1f, 0.9f))) * voxel;
        const glm::vec4 color(u(0, 1), u(0, 1), u(0, 1), u(0.1f, 1.0f));
        p.centerRadius.push_back(glm::vec4(c, r));
        p.color.push_back(color);
        p.id.push_back(std::uint32_t(i));
        p.maxRadius = std::max(p.maxRadius, r);
        // The deposit quantises opacity and colour to 8 bits.
        const double fraction = 4.0 / 3.0 * M_PI * std::pow(double(r) / voxel, 3.0);
        const double opacity = std::round(color.w * 255.0) / 255.0;
        alpha += fraction * opacity;
        red += fraction * opacity * std::round(color.x * 255.0) / 255.0;
    }
    Bounds bounds;
    bounds.extend(glm::vec3(0.0f), 0.0f);
    bounds.extend(glm::vec3(1.0f), 0.0f);
    p.bounds = bounds;
    AoSpec spec;
    spec.resolution = 8;
    gl::SphereAmbient ambient = gl::SphereAmbient::create(spec, /*cached=*/false);
    ambient.voxelize(p, bounds);
    ASSERT_EQ(ambient.size(), glm::ivec3(8));
    ASSERT_FLOAT_EQ(ambient.voxelSize(), voxel);
    const std::vector<glm::vec4> v = ambient.readLevel0();
    const std::size_t t = std::size_t(target.x + 8 * (target.y + 8 * target.z));
    const double tolerance = 400 * 0.5 / (27.0 * 65536.0) + 1e-5 * alpha;
    std::printf("[ info ] voxel alpha %.6f, analytic %.6f (tolerance %.1e)\n", v[t].w, alpha, tolerance);
    EXPECT_NEAR(v[t].w, alpha, tolerance);
    EXPECT_NEAR(v[t].x, red, tolerance);
    EXPECT_GT(alpha, 0.05);  // the cloud is not negligible
    for (std::size_t k = 0; k < v.size(); ++k) {
        if (k == t) continue;
        ASSERT_EQ(v[k], glm::vec4(0.0f)) << k;
    }
    const rt::SphereVolume cpu(spec, p);
    EXPECT_EQ(cpu.fetch(0, target.x, target.y, target.z), v[t]);
}

// The exact volume of sphere s inside the unit voxel at lo (world units = voxels), by midpoint
// integration on a 96^3 grid (error ~1e-4 voxel at these radii).
double overlapVolume(const glm::vec4& s, glm::vec3 lo) {
    const int n = 96;
    const double h = 1.0 / n;
    int inside = 0;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::dvec3 q = glm::dvec3(lo) + (glm::dvec3(x, y, z) + 0.5) * h - glm::dvec3(glm::vec3(s));
                inside += glm::dot(q, q) < double(s.w) * s.w ? 1 : 0;
            }
    return inside * h * h * h;
}

// A sphere straddling voxels (Sect. 5.1's partial overlaps, 3x3x3 sub-samples) splits its volume
// among them: each voxel within its sampling bound (sub-cells the surface cuts / 27) of the exact
// overlap, and in total within 8 % of 4/3 pi r^3 (measured: 5.4 % for r = 0.9 voxel over 16
// voxels, 0.4 % for r = 1.7 over 59: the sampling error shrinks with the radius). Voxels the sphere misses get 0, and
// the CPU twin deposits the same.
TEST_F(SphereAmbientTest, a_sphere_straddling_voxels_splits_its_volume) {
    for (const glm::vec4& s : {glm::vec4(2.3f, 2.05f, 1.6f, 0.9f), glm::vec4(3.1f, 2.6f, 2.95f, 1.7f)}) {
        StyledParticles p = spheres({s});
        Bounds bounds;
        bounds.extend(glm::vec3(0.0f), 0.0f);
        bounds.extend(glm::vec3(6.0f), 0.0f);
        p.bounds = bounds;
        AoSpec spec;
        spec.resolution = 6;  // one world unit per voxel
        gl::SphereAmbient ambient = gl::SphereAmbient::create(spec, /*cached=*/false);
        ambient.voxelize(p, bounds);
        ASSERT_FLOAT_EQ(ambient.voxelSize(), 1.0f);
        const std::vector<glm::vec4> v = ambient.readLevel0();
        const rt::SphereVolume cpu(spec, p);
        double total = 0;
        int touched = 0;
        for (int z = 0; z < 6; ++z)
            for (int y = 0; y < 6; ++y)
                for (int x = 0; x < 6; ++x) {
                    const float w = v[std::size_t(x + 6 * (y + 6 * z))].w;
                    EXPECT_EQ(cpu.fetch(0, x, y, z).w, w) << x << " " << y << " " << z;
                    const glm::vec3 lo(x, y, z);
                    const double exact = overlapVolume(s, lo);
                    const glm::vec4 one(glm::vec3(s) - lo, s.w);  // the sphere relative to this voxel
                    // samplingBound sums over every voxel the sphere touches; keep this voxel's share.
                    double bound = 0;
                    for (int k = 0; k < 27; ++k) {
                        const glm::vec3 sl = glm::vec3(k % 3, (k / 3) % 3, k / 9) / 3.0f;
                        const glm::vec3 n = glm::clamp(glm::vec3(one), sl, sl + 1.0f / 3.0f) - glm::vec3(one);
                        const glm::vec3 f =
                            glm::max(glm::abs(sl - glm::vec3(one)), glm::abs(sl + 1.0f / 3.0f - glm::vec3(one)));
                        bound += glm::dot(n, n) < s.w * s.w && glm::dot(f, f) > s.w * s.w ? 1.0 / 27.0 : 0.0;
                    }
                    EXPECT_NEAR(w, exact, bound + 1e-3) << x << " " << y << " " << z;
                    if (exact == 0.0) {
                        EXPECT_EQ(w, 0.0f);
                    }
                    touched += exact > 0.0 ? 1 : 0;
                    total += w;
                }
        const double volume = 4.0 / 3.0 * M_PI * std::pow(double(s.w), 3.0);
        std::printf("[ info ] r = %.1f voxel over %d voxels: deposited %.4f, analytic %.4f (%.2f %%)\n", s.w, touched,
                    total, volume, 100.0 * std::abs(total - volume) / volume);
        EXPECT_GE(touched, 8);
        EXPECT_NEAR(total, volume, 0.08 * volume);
    }
}

// The GL voxelization and its CPU twin (rt::SphereVolume) on a cloud mixing all three overlap
// cases (radii 0.05..2.5 voxels, random colours and opacities): level 0 agrees voxel for voxel.
TEST_F(SphereAmbientTest, gpu_voxelization_matches_the_cpu_twin) {
    std::mt19937 rng(21);
    auto u = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) / 16777216.0f; };
    StyledParticles p;
    for (int i = 0; i < 3000; ++i) {
        const float r = 0.02f * std::pow(50.0f, u(0, 1)) / 32.0f;  // 0.02 .. 1 voxel at resolution 32, x 2.5
        const glm::vec3 c(u(0, 1), u(0, 1), u(0, 1));
        p.centerRadius.push_back(glm::vec4(c, 2.5f * r));
        p.color.push_back(glm::vec4(u(0, 1), u(0, 1), u(0, 1), u(0, 1)));
        p.id.push_back(std::uint32_t(i));
        p.bounds.extend(c, 2.5f * r);
        p.maxRadius = std::max(p.maxRadius, 2.5f * r);
    }
    AoSpec spec;
    spec.resolution = 32;
    // The primary transfer function, and ambient ones (render.spheres.ambient_*) with a step.
    AmbientTransfer shaped;
    shaped.opacity = {{0.0f, 0.1f}, {0.5f, 0.9f}, {0.5f, 0.4f}, {1.0f, 0.2f}};
    shaped.emission = {{0.0f, 1.0f}, {0.7f, 0.3f}, {1.0f, 0.0f}};
    for (const AmbientTransfer& transfer : {AmbientTransfer{}, shaped}) {
        gl::SphereAmbient ambient = gl::SphereAmbient::create(spec, /*cached=*/false, transfer);
        ambient.voxelize(p, p.bounds);
        const std::vector<glm::vec4> v = ambient.readLevel0();
        const rt::SphereVolume cpu(spec, p, {}, transfer);
        ASSERT_EQ(cpu.size(), ambient.size());
        const glm::ivec3 n = ambient.size();
        std::size_t equal = 0, nonzero = 0;
        float worst = 0;
        for (int z = 0; z < n.z; ++z)
            for (int y = 0; y < n.y; ++y)
                for (int x = 0; x < n.x; ++x) {
                    const glm::vec4 g = v[std::size_t(x + n.x * (y + n.y * z))], c = cpu.fetch(0, x, y, z);
                    equal += g == c ? 1 : 0;
                    nonzero += g.w > 0.0f ? 1 : 0;
                    for (int k = 0; k < 4; ++k) worst = std::max(worst, std::abs(g[k] - c[k]));
                }
        std::printf("[ info ] %zu of %zu voxels bit-identical (%zu non-empty), worst |diff| %.2e\n", equal, v.size(),
                    nonzero, worst);
        EXPECT_GT(nonzero, v.size() / 10);
        // A sub-sample or containment test decided differently by an ulp of c or r (llvmpipe's
        // division) moves at most one sub-sample: 1/27 of a voxel.
        EXPECT_LE(worst, 1.0f / 27.0f);
        EXPECT_GE(double(equal), 0.999 * double(v.size()));
    }
}

class SphereAmbientModes : public GlTest, public ::testing::WithParamInterface<AoSpec::Cache> {};

// Renders `p` opaque (Blinn-Phong x A_O + L_A) with AO, exact per-fragment tracing or the
// per-sphere ambient cube; returns the colour image.
std::vector<float> renderWithAo(const StyledParticles& p, AoSpec::Cache cache, const Camera& cam, int w, int h,
                                float alphaA) {
    Scene scene;
    scene.render.technique = RenderTechnique::Spheres;
    scene.render.transparency = Transparency::Opaque;
    scene.render.ao.enabled = true;
    scene.render.ao.resolution = 64;
    scene.render.ao.cache = cache;
    scene.render.spheres.alphaA = alphaA;
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
    scene.lighting.direction = {0.0f, 0.0f, 1.0f};
    auto renderer = gl::SphereRenderer::create(scene, p);
    FrameImages img;
    gl::StageTimer timer;
    renderer->render(tc::FrameSetup{0, cam, w, h}, img, timer);
    timer.collect();
    return img.rgba;
}

// The ambient cube (6 traced normals per sphere, blended by n^2) against tracing at every
// fragment, on a dense random cluster with coloured ambient light on: the shaded images agree
// to 3 % on average and 25 % at worst (measured 2.2 % / 21 %: the cube is exact at the six axis
// normals and smooth in between, while the exact occlusion changes quickly where spheres touch).
TEST_F(SphereAmbientTest, cached_ambient_cube_matches_per_fragment_tracing) {
    std::mt19937 rng(4);
    auto u = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) / 16777216.0f; };
    std::vector<glm::vec4> cr;
    for (int i = 0; i < 400; ++i) cr.push_back(glm::vec4(u(0, 1), u(0, 1), u(0, 1), u(0.03f, 0.07f)));
    StyledParticles p = spheres(cr);
    for (std::size_t i = 0; i < p.size(); ++i) p.color[i] = glm::vec4(u(0.2f, 1), u(0.2f, 1), u(0.2f, 1), 1.0f);
    Camera cam;
    cam.eye = {0.5f, -1.6f, 1.2f};
    cam.target = {0.5f, 0.5f, 0.5f};
    cam.up = {0, 0, 1};
    const int w = 96, h = 72;
    std::vector<float> exact = renderWithAo(p, AoSpec::Cache::None, cam, w, h, 0.4f);
    std::vector<float> cached = renderWithAo(p, AoSpec::Cache::Precomputed, cam, w, h, 0.4f);
    double sum = 0, worst = 0;
    std::size_t covered = 0;
    for (std::size_t i = 0; i < exact.size(); i += 4) {
        if (exact[i + 3] == 0.0f) continue;
        ++covered;
        for (int c = 0; c < 3; ++c) {
            const double d = std::abs(double(exact[i + c]) - cached[i + c]);
            sum += d / 3.0;
            worst = std::max(worst, d);
        }
    }
    ASSERT_GT(covered, std::size_t(w * h / 4));
    std::printf("[ info ] cached vs exact: mean %.4f, max %.4f over %zu pixels\n", sum / double(covered), worst,
                covered);
    EXPECT_LT(sum / double(covered), 0.03);
    EXPECT_LT(worst, 0.25);
}

TEST_P(SphereAmbientModes, ambient_occlusion_darkens_a_sphere_among_others) {
    // A row of spheres: the middle one's side faces are occluded by its neighbours, the end ones'
    // outer faces are not. Opaque, AO on: compare the shading at the facing points.
    std::vector<glm::vec4> cr;
    for (int i = 0; i < 5; ++i) cr.push_back(glm::vec4(0.25f * float(i), 0.0f, 0.0f, 0.11f));
    StyledParticles p = spheres(cr);
    Scene scene;
    scene.render.technique = RenderTechnique::Spheres;
    scene.render.transparency = Transparency::Opaque;
    scene.render.ao.enabled = true;
    scene.render.ao.resolution = 64;
    scene.render.ao.cache = GetParam();
    scene.render.spheres.alphaA = 0.0f;
    scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
    scene.lighting.direction = {0.0f, 0.0f, 1.0f};
    auto renderer = gl::SphereRenderer::create(scene, p);
    Camera cam;
    cam.eye = {0.5f, 0.0f, 3.0f};
    cam.target = {0.5f, 0.0f, 0.0f};
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 0.5f;
    const int w = 160, h = 40;
    FrameImages img;
    gl::StageTimer timer;
    renderer->render(tc::FrameSetup{0, cam, w, h}, img, timer);
    timer.collect();
    // Pixel at world x: column (x - 0.5) / (0.5 * 4) * w + w / 2 (ortho width = 0.5 * 4 = 2).
    auto lum = [&](float x) {
        int px = int(std::floor((x - 0.5f) / 2.0f * w + w / 2.0f));
        return img.rgba[4 * std::size_t((h / 2) * w + px)];
    };
    // Points 0.09 right of a centre: the middle sphere's side faces sphere 3, the last sphere's
    // outer side faces nothing.
    const float inner = lum(0.5f + 0.09f), outer = lum(1.0f + 0.09f);
    EXPECT_GT(outer, 0.0f);
    EXPECT_LT(inner, outer * 0.97f) << inner << " vs " << outer;
}

// Staib et al. 2015, Sect. 3.2: the ambient transfer functions tau_A and e_A
// (render.spheres.ambient_opacity / ambient_emission) act on the ambient terms and only on them.
// Transparent spheres with AO and coloured ambient light on a dense cluster:
//   - ambient opacity 0 empties the volume: A_O = 1, L_A = 0, the image without AO;
//   - ambient emission 0 keeps A_O and removes L_A: the image with alpha_a = 0;
//   - a partial ambient opacity changes the image; the identity functions give the default image;
//   - without AO the functions change nothing.
TEST_F(SphereAmbientTest, ambient_transfer_functions_change_the_ambient_terms_and_only_them) {
    std::mt19937 rng(8);
    auto u = [&](float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) / 16777216.0f; };
    std::vector<glm::vec4> cr;
    for (int i = 0; i < 400; ++i) cr.push_back(glm::vec4(u(0, 1), u(0, 1), u(0, 1), u(0.03f, 0.07f)));
    StyledParticles p = spheres(cr);
    for (std::size_t i = 0; i < p.size(); ++i) p.color[i] = glm::vec4(u(0.2f, 1), u(0.2f, 1), u(0.2f, 1), u(0.3f, 1));
    Camera cam;
    cam.eye = {0.5f, -1.6f, 1.2f};
    cam.target = {0.5f, 0.5f, 0.5f};
    cam.up = {0, 0, 1};
    const int w = 96, h = 72;
    auto render = [&](bool ao, float alphaA, const AmbientTransfer& transfer) {
        Scene scene;
        scene.render.technique = RenderTechnique::Spheres;
        scene.render.transparency = Transparency::ObjectOrder;
        scene.render.spheres.chunks = 1;
        scene.render.ao.enabled = ao;
        scene.render.ao.resolution = 48;
        scene.render.spheres.alphaA = alphaA;
        scene.render.spheres.ambient = transfer;
        scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = false;
        auto renderer = gl::SphereRenderer::create(scene, p);
        FrameImages img;
        gl::StageTimer timer;
        renderer->render(tc::FrameSetup{0, cam, w, h}, img, timer);
        timer.collect();
        return img.rgba;
    };
    auto maxDiff = [](const std::vector<float>& a, const std::vector<float>& b) {
        float m = 0;
        for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
        return m;
    };
    const std::vector<glm::vec2> zero{{0.0f, 0.0f}, {1.0f, 0.0f}};
    AmbientTransfer noOpacity, noEmission, half, identity;
    noOpacity.opacity = zero;
    noEmission.emission = zero;
    half.opacity = {{0.0f, 0.0f}, {1.0f, 0.5f}};
    identity.opacity = {{0.0f, 0.0f}, {1.0f, 1.0f}};
    identity.emission = {{0.0f, 1.0f}, {1.0f, 1.0f}};

    const std::vector<float> base = render(true, 0.6f, {});
    const std::vector<float> noAo = render(false, 0.6f, {});
    const std::vector<float> noLight = render(true, 0.0f, {});
    ASSERT_GT(maxDiff(base, noAo), 0.05f);     // AO and L_A show in this scene ...
    ASSERT_GT(maxDiff(base, noLight), 0.05f);  // ... and L_A alone too
    // The programs with and without AMBIENT_OCCLUSION are compiled differently (llvmpipe contracts
    // other multiply-adds; measured 2.5e-5), hence not 0.
    EXPECT_LE(maxDiff(render(true, 0.6f, noOpacity), noAo), 1e-4f);
    EXPECT_LE(maxDiff(render(true, 0.6f, noEmission), noLight), 1e-6f);
    const float halfDiff = maxDiff(render(true, 0.6f, half), base);
    const float identityDiff = maxDiff(render(true, 0.6f, identity), base);
    std::printf("[ info ] ambient opacity x 0.5: max |diff| %.3f; identity functions: %.2e\n", halfDiff, identityDiff);
    EXPECT_GT(halfDiff, 0.02f);
    EXPECT_LE(identityDiff, 1e-6f);
    EXPECT_EQ(render(false, 0.6f, noOpacity), noAo);
    EXPECT_EQ(render(false, 0.6f, half), noAo);
}

INSTANTIATE_TEST_SUITE_P(ExactAndCached, SphereAmbientModes,
                         ::testing::Values(AoSpec::Cache::None, AoSpec::Cache::Precomputed));

}  // namespace
}  // namespace tc::test
