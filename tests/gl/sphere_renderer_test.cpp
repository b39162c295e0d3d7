// Sphere glyphs (gl/sphere_renderer.h, Staib, Grottel & Gumhold 2015) against ground truth: the
// CPU reference compositor (core/particle_reference.h) on disjoint spheres whose radii vary 10x
// (so a sort by centre distance instead of power distance shows), the analytic opacity profile
// of one sphere, and the early-z chunks against the unchunked image within the threshold bound;
// point-sprite billboards against quads (identical images, and the fallback to quads for spheres
// larger than the largest point).
#include "gl/sphere_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/particle_generators.h"
#include "core/particle_reference.h"
#include "core/particle_styling.h"
#include "core/scene.h"
#include "core/sphere_glyph.h"
#include "gl/gpu_timer.h"
#include "gl_fixture.h"

namespace tc::test {
namespace {

// GPU vs CPU reference, linear premultiplied colour and alpha, absolute. Both evaluate the same
// formulas (core/sphere_glyph.h and its GLSL twin) in fp32 on the same rays; llvmpipe's
// exp2/log2/pow/sqrt approximations and contracted multiply-adds differ by ulps; the worst pixel
// measured 4.9e-5 (constant), 4.4e-5 (l2), 3.5e-5 (hollow), mostly from pow(., 32) of the
// specular term. A swapped pair of overlapping spheres changes a pixel by a1 a2 |c1 - c2|, ~1e-2
// and more here.
constexpr float kReferenceTolerance = 2e-4f;
// Pixels whose ray passes within this fraction of a radius of a silhouette are not compared: a
// grazing ray may hit on one side and miss on the other (opacity there < 1e-3 anyway).
constexpr float kGrazing = 1e-3f;

struct Uniform {  // std::mt19937's raw output only (the distributions are implementation-defined)
    std::mt19937 rng;
    explicit Uniform(std::uint32_t seed) : rng(seed) {}
    float operator()(float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) * (1.0f / 16777216.0f); }
};

// Disjoint spheres with radii 0.03 .. 0.3 (10x) in a 2x2x2 box, random colours and opacities.
StyledParticles disjointSpheres(std::uint32_t seed, int count, const std::vector<glm::vec4>& initial = {}) {
    Uniform u(seed);
    StyledParticles p;
    for (const glm::vec4& q : initial) {
        p.centerRadius.push_back(q);
        p.color.push_back(glm::vec4(u(0, 1), u(0, 1), u(0, 1), u(0.4f, 0.9f)));
        p.id.push_back(std::uint32_t(p.id.size()));
        p.bounds.extend(glm::vec3(q), q.w);
        p.maxRadius = std::max(p.maxRadius, q.w);
    }
    int attempts = 0;
    while (int(p.size()) < count && ++attempts < 100000) {
        glm::vec3 c(u(-1, 1), u(-1, 1), u(-1, 1));
        float r = 0.03f * std::pow(10.0f, u(0, 1));
        bool ok = true;
        for (const glm::vec4& q : p.centerRadius)
            if (glm::distance(c, glm::vec3(q)) < r + q.w + 0.01f) ok = false;
        if (!ok) continue;
        p.centerRadius.push_back(glm::vec4(c, r));
        p.color.push_back(glm::vec4(u(0, 1), u(0, 1), u(0, 1), u(0.2f, 0.9f)));
        p.id.push_back(std::uint32_t(p.id.size()));
        p.bounds.extend(c, r);
        p.maxRadius = std::max(p.maxRadius, r);
    }
    return p;
}

Scene sphereScene(Transparency t, SphereDensity density, int chunks) {
    Scene s;
    s.render.technique = RenderTechnique::Spheres;
    s.render.transparency = t;
    s.render.spheres.density = density;
    s.render.spheres.chunks = chunks;
    s.render.spheres.innerRadius = 0.6f;
    s.output.aovDepth = s.output.aovNormal = s.output.aovId = false;
    return s;
}

FrameImages renderGpu(const Scene& scene, const StyledParticles& p, const Camera& cam, int w, int h,
                      std::unique_ptr<gl::SphereRenderer>* keep = nullptr) {
    Scene s = scene;
    s.image.width = w;
    s.image.height = h;
    auto r = gl::SphereRenderer::create(s, p);
    gl::StageTimer timer;
    FrameImages img;
    r->render(tc::FrameSetup{0, cam, w, h}, img, timer);
    timer.collect();
    if (keep) *keep = std::move(r);
    return img;
}

// Rays that graze a silhouette (|d - r| < kGrazing r) for any sphere.
bool grazing(const StyledParticles& p, const Camera& cam, int w, int h, int x, int y) {
    Ray ray = pixelRay(cam, w, h, float(x), float(y));
    for (const glm::vec4& q : p.centerRadius) {
        SphereInterval s = intersectSphere(ray, glm::vec3(q), q.w);
        if (std::abs(std::sqrt(s.dist2) - q.w) < kGrazing * q.w) return true;
    }
    return false;
}

class SphereRendererTest : public GlTest {};

TEST_F(SphereRendererTest, transparent_spheres_match_cpu_reference_with_radii_varying_10x) {
    Camera cam;
    cam.eye = {0.4f, 0.7f, 3.2f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 60.0f;  // wide: perspective bounds matter at the edges
    const int w = 96, h = 72;
    // A big sphere A and a small one B (30x smaller) tucked behind A's limb: B's centre is nearer
    // to the eye than A's, but A is in front of B along the rays they share. A sort by centre
    // distance draws B first; the power distance (and the reference) puts A first.
    const glm::vec4 a(0.0f, 0.0f, 0.0f, 0.6f);
    const glm::vec3 toA = glm::normalize(glm::vec3(a) - cam.eye);
    const glm::vec3 side = glm::normalize(glm::cross(toA, glm::vec3(0.0f, 1.0f, 0.0f)));
    const float limb = std::asin(a.w / glm::distance(cam.eye, glm::vec3(a)));
    const glm::vec3 dir = std::cos(0.9995f * limb) * toA + std::sin(0.9995f * limb) * side;
    const SphereInterval through = intersectSphere(Ray{cam.eye, dir}, glm::vec3(a), a.w);
    ASSERT_TRUE(through.hit);
    const glm::vec4 b(cam.eye + (through.tFar + 0.022f) * dir, 0.02f);
    ASSERT_LT(glm::distance(cam.eye, glm::vec3(b)), glm::distance(cam.eye, glm::vec3(a)));
    const StyledParticles p = disjointSpheres(11, 40, {a, b});
    ASSERT_GE(p.size(), 35u);

    // The scene must be able to catch a wrong key: pairs that overlap on screen whose centre-
    // distance order differs from their power-distance order.
    int discriminating = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j) {
            glm::vec4 a, b;
            if (!projectedSphereBounds(cam, float(w) / h, glm::vec3(p.centerRadius[i]), p.centerRadius[i].w, 0, a) ||
                !projectedSphereBounds(cam, float(w) / h, glm::vec3(p.centerRadius[j]), p.centerRadius[j].w, 0, b))
                continue;
            if (a.x > b.z || b.x > a.z || a.y > b.w || b.y > a.w) continue;
            bool byCentre = glm::distance(cam.eye, glm::vec3(p.centerRadius[i])) <
                            glm::distance(cam.eye, glm::vec3(p.centerRadius[j]));
            bool byPower = powerDistance(cam.eye, glm::vec3(p.centerRadius[i]), p.centerRadius[i].w) <
                           powerDistance(cam.eye, glm::vec3(p.centerRadius[j]), p.centerRadius[j].w);
            discriminating += byCentre != byPower;
        }
    EXPECT_GT(discriminating, 0);

    for (SphereDensity d : {SphereDensity::Constant, SphereDensity::L2, SphereDensity::HollowConstant}) {
        Scene scene = sphereScene(Transparency::ObjectOrder, d, 1);
        ParticleReferenceOptions o;
        o.spheres = scene.render.spheres;
        o.lighting = scene.lighting;
        FrameImages ref = renderParticlesReference(p, cam, w, h, o);
        FrameImages gpu = renderGpu(scene, p, cam, w, h);
        float worst = 0;
        int compared = 0, covered = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (grazing(p, cam, w, h, x, y)) continue;
                ++compared;
                const std::size_t i = std::size_t(y * w + x);
                covered += ref.rgba[4 * i + 3] > 0;
                for (int c = 0; c < 4; ++c)
                    worst = std::max(worst, std::abs(gpu.rgba[4 * i + c] - ref.rgba[4 * i + c]));
            }
        EXPECT_GT(covered, w * h / 10);
        EXPECT_GT(compared, w * h * 9 / 10);
        EXPECT_LE(worst, kReferenceTolerance) << "density " << int(d);
        std::printf("[ info ] density %d: max |GPU - CPU| = %.3g over %d pixels\n", int(d), worst, compared);
    }
}

TEST_F(SphereRendererTest, opaque_spheres_match_reference_first_hit_and_ids) {
    const StyledParticles p = disjointSpheres(5, 30);
    Camera cam;
    cam.eye = {-0.5f, 0.3f, 3.0f};
    const int w = 80, h = 60;
    Scene scene = sphereScene(Transparency::Opaque, SphereDensity::Constant, 1);
    scene.output.aovDepth = scene.output.aovId = true;
    ParticleReferenceOptions o;
    o.opaque = true;
    o.lighting = scene.lighting;
    FrameImages ref = renderParticlesReference(p, cam, w, h, o);
    FrameImages gpu = renderGpu(scene, p, cam, w, h);
    int mismatches = 0;
    float worst = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (grazing(p, cam, w, h, x, y)) continue;
            const std::size_t i = std::size_t(y * w + x);
            mismatches += gpu.id[i] != ref.id[i];
            if (ref.id[i] == kBackgroundId) continue;
            worst = std::max(worst, std::abs(gpu.depth[i] - ref.depth[i]) / ref.depth[i]);
            for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(gpu.rgba[4 * i + c] - ref.rgba[4 * i + c]));
        }
    EXPECT_EQ(mismatches, 0);
    EXPECT_LE(worst, kReferenceTolerance);
}

TEST_F(SphereRendererTest, opacity_profile_of_one_sphere_matches_closed_form) {
    StyledParticles p;
    p.centerRadius = {{0.0f, 0.0f, 0.0f, 0.9f}};
    p.color = {{1.0f, 1.0f, 1.0f, 0.6f}};
    p.id = {0};
    p.bounds.extend(glm::vec3(0.0f), 0.9f);
    p.maxRadius = 0.9f;
    Camera cam;  // orthographic: every ray parallel, the profile is exactly alpha(d)
    cam.projection = Projection::Orthographic;
    cam.orthoHeight = 2.0f;
    const int n = 129;  // odd: a pixel centre on the sphere's centre
    for (SphereDensity d : {SphereDensity::Constant, SphereDensity::L2}) {
        FrameImages img = renderGpu(sphereScene(Transparency::ObjectOrder, d, 1), p, cam, n, n);
        const int c = n / 2;
        float best = 0, bestD = 0;
        for (int x = c; x < n; ++x) {
            const float dist = 2.0f * (float(x) + 0.5f) / float(n) - 1.0f;
            const float a = img.rgba[4 * std::size_t(c * n + x) + 3];
            const float expected =
                sphereRayOpacity(d, 0.0f, 0.6f, Ray{{dist, 0.0f, 3.0f}, {0, 0, -1}}, glm::vec3(0.0f), 0.9f);
            EXPECT_NEAR(a, expected, 1e-5f) << x;
            if (a > best) best = a, bestD = dist;
        }
        if (d == SphereDensity::Constant) {
            EXPECT_NEAR(img.rgba[4 * std::size_t(c * n + c) + 3], 0.6f, 1e-5f);  // Theta_max at the centre
        } else {
            EXPECT_NEAR(best, 0.6f, 1e-3f);                        // the peak is Theta_max ...
            EXPECT_NEAR(bestD, 0.9f / std::sqrt(2.0f), 2.0f / n);  // ... at r / sqrt(2), to a pixel
        }
    }
    // A far perspective camera (orthographic-like) sees Theta_max at the projected centre too.
    Camera far;
    far.eye = {0.0f, 0.0f, 200.0f};
    far.fovYDeg = 0.6f;
    FrameImages img = renderGpu(sphereScene(Transparency::ObjectOrder, SphereDensity::Constant, 1), p, far, 33, 33);
    EXPECT_NEAR(img.rgba[4 * std::size_t(16 * 33 + 16) + 3], 0.6f, 1e-4f);
}

// Staib et al. 2015, Eq. 2: alpha_rv weights the volume emission. alpha_rv = 1 on opaque-
// opacity particles draws exactly their colour at every covered pixel; at alpha_rv = 0.2 the
// image (mostly shading) matches the CPU reference within the reference tolerance.
TEST_F(SphereRendererTest, alpha_rv_weights_the_volume_emission_as_eq2_and_matches_the_reference) {
    StyledParticles p = disjointSpheres(5, 12);
    for (glm::vec4& c : p.color) c.w = 1.0f;
    Camera cam;
    cam.eye = {0.4f, 0.7f, 3.2f};
    const int w = 64, h = 48;
    Scene scene = sphereScene(Transparency::ObjectOrder, SphereDensity::Constant, 1);
    scene.render.spheres.alphaRv = 1.0f;
    const FrameImages plain = renderGpu(scene, p, cam, w, h);
    ParticleReferenceOptions o;
    o.spheres = scene.render.spheres;
    o.lighting = scene.lighting;
    const FrameImages plainRef = renderParticlesReference(p, cam, w, h, o);
    int covered = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y * w + x);
            if (plain.rgba[4 * i + 3] < 1.0f || plainRef.rgba[4 * i + 3] < 1.0f || grazing(p, cam, w, h, x, y))
                continue;
            ++covered;
            // The first sphere along the ray (the reference's id) is opaque: its colour alone.
            const glm::vec4& c = p.color[plainRef.id[i]];
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(plain.rgba[4 * i + std::size_t(k)], c[k], 1e-6f) << x << " " << y;
        }
    EXPECT_GT(covered, 200);

    scene.render.spheres.alphaRv = 0.2f;
    o.spheres = scene.render.spheres;
    for (glm::vec4& c : p.color) c.w = 0.7f;
    const FrameImages mixed = renderGpu(scene, p, cam, w, h);
    const FrameImages mixedRef = renderParticlesReference(p, cam, w, h, o);
    float worst = 0, shading = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (grazing(p, cam, w, h, x, y)) continue;
            const std::size_t i = std::size_t(y * w + x);
            for (int k = 0; k < 4; ++k)
                worst = std::max(worst,
                                 std::abs(mixed.rgba[4 * i + std::size_t(k)] - mixedRef.rgba[4 * i + std::size_t(k)]));
            shading = std::max(shading, std::abs(mixed.rgba[4 * i] - plain.rgba[4 * i] * 0.7f));
        }
    EXPECT_LE(worst, kReferenceTolerance);
    EXPECT_GT(shading, 0.05f);  // alpha_rv 0.2 is mostly the shaded surface, not the flat colour
}

TEST_F(SphereRendererTest, early_z_chunks_stay_within_threshold_and_skip_fragments_on_dense_scene) {
    Scene scene = sphereScene(Transparency::ObjectOrder, SphereDensity::Constant, 1);
    scene.style.opacity.constant = 0.5f;
    scene.style.radius.constant = 0.02f;
    ParticleSet droplets = generateDroplets(20000, 3);
    droplets.radii.clear();  // the constant radius: bigger than LJ contact, a dense image
    StyledParticles p = styleParticles(droplets, scene.style, "");
    Camera cam;
    cam.eye = {0.5f, 0.5f, 2.2f};
    cam.target = {0.5f, 0.5f, 0.5f};
    const int w = 128, h = 96;
    std::unique_ptr<gl::SphereRenderer> plain, chunked;
    FrameImages a = renderGpu(scene, p, cam, w, h, &plain);
    EXPECT_EQ(plain->lastSkippedFragments(), 0u);
    const float threshold = 0.9f;
    scene.render.spheres.chunks = 20;
    scene.render.spheres.earlyZThreshold = threshold;
    scene.render.spheres.earlyZStats = true;
    FrameImages b = renderGpu(scene, p, cam, w, h, &chunked);
    // A skipped fragment lands behind accumulated alpha > threshold: everything behind adds at
    // most (1 - alpha) <= 1 - threshold to any channel (premultiplied, colours clamped to [0, 1]).
    float worst = 0;
    int saturated = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) worst = std::max(worst, std::abs(a.rgba[i] - b.rgba[i]));
    for (std::size_t i = 0; i < a.pixelCount(); ++i) saturated += a.rgba[4 * i + 3] > threshold;
    EXPECT_LE(worst, 1.0f - threshold + 1e-5f);
    EXPECT_GT(saturated, w * h / 20);  // a dense scene
    EXPECT_GT(chunked->lastSkippedFragments(), 0u);
    EXPECT_GT(worst, 0.0f);  // something was skipped that mattered a little
    std::printf("[ info ] early-z: %llu fragments skipped, %llu shaded, max diff %.3g\n",
                (unsigned long long)chunked->lastSkippedFragments(), (unsigned long long)chunked->lastShadedFragments(),
                worst);
}

TEST_F(SphereRendererTest, point_sprites_draw_the_same_images_as_quads_and_fall_back_for_huge_spheres) {
    const StyledParticles p = disjointSpheres(5, 60);
    Camera cam;
    cam.eye = {0.3f, -0.6f, 3.4f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 50.0f;
    const int w = 120, h = 90;
    for (Transparency t : {Transparency::Opaque, Transparency::ObjectOrder}) {
        Scene scene = sphereScene(t, SphereDensity::L2, 4);
        scene.output.aovDepth = scene.output.aovNormal = scene.output.aovId = true;
        std::unique_ptr<gl::SphereRenderer> points, quads;
        scene.render.spheres.points = true;
        FrameImages a = renderGpu(scene, p, cam, w, h, &points);
        scene.render.spheres.points = false;
        FrameImages b = renderGpu(scene, p, cam, w, h, &quads);
        EXPECT_FALSE(points->lastFrameUsedQuads());
        EXPECT_TRUE(quads->lastFrameUsedQuads());
        // Same fragments (each pixel centre of the bounds rectangle), same shader: bit-identical.
        EXPECT_EQ(a.rgba, b.rgba);
        EXPECT_EQ(a.depth, b.depth);
        EXPECT_EQ(a.id, b.id);
        int covered = 0;
        for (std::size_t i = 0; i < a.pixelCount(); ++i) covered += a.rgba[4 * i + 3] > 0.0f;
        EXPECT_GT(covered, w * h / 10);
    }
    // The eye close to a sphere: it covers more than the largest point sprite (llvmpipe: 255 px)
    // on a 256 px image, so the frame is drawn again with quads and equals the quads image.
    Camera near = cam;
    near.eye = glm::vec3(p.centerRadius[0]) + glm::vec3(0.0f, 0.0f, 1.3f * p.centerRadius[0].w);
    near.target = glm::vec3(p.centerRadius[0]);
    Scene scene = sphereScene(Transparency::ObjectOrder, SphereDensity::Constant, 4);
    std::unique_ptr<gl::SphereRenderer> points, quads;
    scene.render.spheres.points = true;
    FrameImages a = renderGpu(scene, p, near, 256, 256, &points);
    scene.render.spheres.points = false;
    FrameImages b = renderGpu(scene, p, near, 256, 256, &quads);
    EXPECT_TRUE(points->lastFrameUsedQuads());
    EXPECT_EQ(a.rgba, b.rgba);
    EXPECT_GT(a.rgba[4 * std::size_t(128 * 256 + 128) + 3], 0.0f);  // the near sphere is there
}

}  // namespace
}  // namespace tc::test
