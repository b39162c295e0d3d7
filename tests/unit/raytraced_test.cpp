// The Embree ray tracer (rt/) against the CPU references of core/: opaque depth / normal / id ==
// renderReferenceOpaque, exact transparent == renderReferenceTransparent (with and without cap
// clipping), determinism across thread counts, the alpha cutoff bound, and the CPU AO ports.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "core/cpu_reference.h"
#include "core/transparent_reference.h"
#include "rt/cone_traced_ao.h"
#include "rt/hit_collector.h"
#include "rt/raytraced_renderer.h"

namespace tc {
namespace {

struct PolylineSpec {
    std::vector<glm::vec4> points;  // xyz, radius
    glm::vec4 color;                // rgb, alpha at the first vertex
    glm::vec4 color2;               // at the last vertex (linear in between)
};

// The layout styleLines builds: contiguous polylines, segments (v, v + 1), flags at the ends.
StyledLines makeLines(const std::vector<PolylineSpec>& polylines) {
    StyledLines l;
    for (std::size_t p = 0; p < polylines.size(); ++p) {
        const auto& pl = polylines[p];
        const std::uint32_t begin = std::uint32_t(l.positionRadius.size());
        const std::size_t n = pl.points.size();
        for (std::size_t k = 0; k < n; ++k) {
            const float s = n > 1 ? float(k) / float(n - 1) : 0.0f;
            l.positionRadius.push_back(pl.points[k]);
            l.color.push_back(glm::mix(pl.color, pl.color2, s));
            l.polylineId.push_back(std::uint32_t(p));
            l.flags.push_back((k == 0 ? FirstOfPolyline : 0u) | (k + 1 == n ? LastOfPolyline : 0u));
            l.bounds.extend(glm::vec3(pl.points[k]), pl.points[k].w);
            l.maxRadius = std::max(l.maxRadius, pl.points[k].w);
        }
        for (std::size_t k = 0; k + 1 < n; ++k) {
            l.segmentVertices.push_back(begin + std::uint32_t(k));
            l.segmentVertices.push_back(begin + std::uint32_t(k) + 1);
        }
    }
    return l;
}

// Random bent polylines: 3..6 vertices, steps of 0.25..0.5 turning by up to ~70 degrees.
// constantRadius: one radius per polyline (the case cap clipping tiles exactly).
std::vector<PolylineSpec> randomPolylines(unsigned seed, int count, bool constantRadius, float alphaLo, float alphaHi) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-0.7f, 0.7f), rad(0.04f, 0.14f), col(0.05f, 1.0f),
        alpha(alphaLo, alphaHi), step(0.25f, 0.5f), turn(-1.2f, 1.2f);
    std::uniform_int_distribution<int> verts(3, 6);
    std::vector<PolylineSpec> out;
    for (int i = 0; i < count; ++i) {
        PolylineSpec pl;
        glm::vec3 p(pos(rng), pos(rng), pos(rng));
        glm::vec3 d = glm::normalize(glm::vec3(pos(rng), pos(rng), pos(rng)) + glm::vec3(1e-3f));
        const float r0 = rad(rng);
        const int n = verts(rng);
        for (int k = 0; k < n; ++k) {
            pl.points.push_back(glm::vec4(p, constantRadius ? r0 : rad(rng)));
            glm::vec3 axis = glm::normalize(glm::cross(d, glm::vec3(pos(rng), pos(rng), pos(rng))) + glm::vec3(1e-4f));
            const float a = turn(rng);
            // Rodrigues rotation of d about axis.
            d = glm::normalize(d * std::cos(a) + glm::cross(axis, d) * std::sin(a) +
                               axis * glm::dot(axis, d) * (1.0f - std::cos(a)));
            p += step(rng) * d;
        }
        pl.color = {col(rng), col(rng), col(rng), alpha(rng)};
        pl.color2 = {col(rng), col(rng), col(rng), alpha(rng)};
        out.push_back(pl);
    }
    return out;
}

Scene sceneFor(Transparency transparency, bool capClipping, float cutoff = 1.0f, bool exactSurface = true) {
    Scene s;
    s.render.raytracedExactSurface = exactSurface;
    s.render.technique = RenderTechnique::Raytraced;
    s.render.transparency = transparency;
    s.render.capClipping = capClipping;
    s.render.raytracedAlphaCutoff = cutoff;
    s.output.aovDepth = s.output.aovNormal = s.output.aovId = true;  // every AOV, to compare
    return s;
}

// `exactSurface`: whether the frame took the exact surface (RaytracedRenderer::lastFrameExactSurface).
FrameImages raytrace(const Scene& scene, const StyledLines& lines, const Camera& cam, int w, int h,
                     std::uint64_t* hits = nullptr, bool* exactSurface = nullptr) {
    auto r = rt::RaytracedRenderer::create(scene, lines);
    FrameImages img;
    tc::CpuStageTimer timer;
    r->render(cam, w, h, img, timer);
    if (hits) *hits = r->lastHitCount();
    if (exactSurface) *exactSurface = r->lastFrameExactSurface();
    return img;
}

Camera cameraAt(glm::vec3 eye, Projection projection = Projection::Perspective) {
    Camera cam;
    cam.eye = eye;
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovYDeg = 40.0f;
    cam.projection = projection;
    cam.orthoHeight = 2.4f;
    return cam;
}

// Pixels where exactly one side sees a surface, or ids differ, are counted, not failed: rays through
// a silhouette or through the rim at a joint (measure-zero sets) may be decided either way by
// Embree's and our float operations. Everywhere else the values must agree closely.
struct OpaqueDiff {
    int covered = 0, mismatched = 0;
    float maxColor = 0;  // over the pixels that agree in id and depth
    float minNormalDot = 1;
};

OpaqueDiff compareOpaque(const FrameImages& rt, const FrameImages& ref, float colorTolerance = 1e-4f) {
    OpaqueDiff d;
    for (std::size_t i = 0; i < ref.pixelCount(); ++i) {
        const bool a = rt.id[i] != kBackgroundId, b = ref.id[i] != kBackgroundId;
        d.covered += b;
        if (a != b || rt.id[i] != ref.id[i]) {
            ++d.mismatched;
            continue;
        }
        if (!b) {
            EXPECT_EQ(rt.depth[i], ref.depth[i]);
            EXPECT_EQ(rt.rgba[4 * i + 3], 0.0f);
            continue;
        }
        if (std::abs(rt.depth[i] - ref.depth[i]) > 1e-5f * std::max(1.0f, ref.depth[i])) {
            ++d.mismatched;  // the same polyline, another segment at a joint (checked below in total)
            continue;
        }
        glm::vec3 n1(rt.normal[3 * i], rt.normal[3 * i + 1], rt.normal[3 * i + 2]);
        glm::vec3 n2(ref.normal[3 * i], ref.normal[3 * i + 1], ref.normal[3 * i + 2]);
        EXPECT_GT(glm::dot(n1, n2), 0.99999f) << i;
        d.minNormalDot = std::min(d.minNormalDot, glm::dot(n1, n2));
        for (int c = 0; c < 4; ++c) {
            EXPECT_NEAR(rt.rgba[4 * i + c], ref.rgba[4 * i + c], colorTolerance) << i;
            d.maxColor = std::max(d.maxColor, std::abs(rt.rgba[4 * i + c] - ref.rgba[4 * i + c]));
        }
    }
    return d;
}

// `uniformColor`: every vertex gets the first one's colour (the renderer then reads no vertex data
// to shade, RaytracedRenderer::m_uniformColor).
OpaqueDiff opaqueAgainstTheReferenceOnRandomTubes(bool exactSurface, bool uniformColor = false) {
    LightingSpec light;
    const int w = 64, h = 48;
    OpaqueDiff total;
    for (unsigned seed : {1u, 2u, 3u}) {
        StyledLines lines = makeLines(randomPolylines(seed, 8, false, 1.0f, 1.0f));
        if (uniformColor) std::fill(lines.color.begin(), lines.color.end(), lines.color[0]);
        for (Projection projection : {Projection::Perspective, Projection::Orthographic}) {
            Camera cam = cameraAt({0.4f, 0.8f, 3.0f}, projection);
            FrameImages rt = raytrace(sceneFor(Transparency::Opaque, true, 1.0f, exactSurface), lines, cam, w, h);
            FrameImages ref = renderReferenceOpaque(lines, cam, light, w, h);
            OpaqueDiff d = compareOpaque(rt, ref, exactSurface ? 1e-4f : 1.0f / 255.0f);
            total.covered += d.covered;
            total.mismatched += d.mismatched;
            total.maxColor = std::max(total.maxColor, d.maxColor);
            total.minNormalDot = std::min(total.minNormalDot, d.minNormalDot);
        }
    }
    return total;
}

TEST(Raytraced, opaque_exact_surface_depth_normal_id_equal_the_cpu_reference_on_random_bent_tubes) {
    OpaqueDiff d = opaqueAgainstTheReferenceOnRandomTubes(true);
    EXPECT_GT(d.covered, 3000);
    // Measured: 0 of ~6000; the allowance is for silhouette pixels under other float behaviour.
    EXPECT_LE(d.mismatched, d.covered / 200) << d.mismatched << " of " << d.covered;
}

TEST(Raytraced, opaque_embree_surface_depth_normal_id_agree_with_the_cpu_reference_on_random_bent_tubes) {
    // render.raytraced.surface "embree": Embree's own hit, held to the same bounds as "exact".
    OpaqueDiff d = opaqueAgainstTheReferenceOnRandomTubes(false);
    EXPECT_GT(d.covered, 3000);
    EXPECT_LE(d.mismatched, d.covered / 200) << d.mismatched << " of " << d.covered;
    std::printf("max colour difference %g, min normal dot %.9f\n", d.maxColor, d.minNormalDot);
}

TEST(Raytraced, opaque_uniform_colour_shades_like_the_cpu_reference) {
    // One colour for every vertex: shaded from that colour without reading the segment's vertices,
    // the same image as the reference's interpolation between equal colours (within 1e-4).
    for (bool exactSurface : {true, false}) {
        OpaqueDiff d = opaqueAgainstTheReferenceOnRandomTubes(exactSurface, true);
        EXPECT_GT(d.covered, 3000);
        EXPECT_LE(d.mismatched, d.covered / 200) << d.mismatched << " of " << d.covered;
    }
}

TEST(Raytraced, opaque_eye_inside_a_tube_sees_its_inner_wall_like_the_reference) {
    LightingSpec light;
    const int w = 48, h = 48;
    // A thick bent polyline around the eye and a thin one crossing in front.
    std::vector<PolylineSpec> pls = {
        {{{-1.0f, 0.0f, 2.0f, 0.5f}, {0.0f, 0.1f, 3.0f, 0.6f}, {1.0f, 0.3f, 2.2f, 0.4f}},
         {0.8f, 0.3f, 0.2f, 1},
         {0.2f, 0.3f, 0.9f, 1}},
        {{{-0.5f, -0.5f, 0.0f, 0.1f}, {0.5f, 0.5f, 0.0f, 0.1f}}, {0.1f, 0.9f, 0.2f, 1}, {0.1f, 0.9f, 0.2f, 1}},
    };
    StyledLines lines = makeLines(pls);
    // Orthographic: the rays start on the plane through the eye, the thick tube crosses it.
    for (Projection projection : {Projection::Perspective, Projection::Orthographic}) {
        Camera cam = cameraAt({0.0f, 0.1f, 3.0f}, projection);
        FrameImages ref = renderReferenceOpaque(lines, cam, light, w, h);
        for (bool exactSurface : {true, false}) {
            // "embree" must notice that rays start in a tube and take the exact surface.
            bool tookExact = false;
            FrameImages rt = raytrace(sceneFor(Transparency::Opaque, true, 1.0f, exactSurface), lines, cam, w, h,
                                      nullptr, &tookExact);
            EXPECT_TRUE(tookExact);
            OpaqueDiff d = compareOpaque(rt, ref, exactSurface ? 1e-4f : 1.0f / 255.0f);
            if (projection == Projection::Perspective) {
                EXPECT_EQ(d.covered, w * h);  // every ray leaves the tube
            }
            EXPECT_GT(d.covered, w * h / 4);
            EXPECT_LE(d.mismatched, d.covered / 100) << d.mismatched << (exactSurface ? " exact" : " embree");
        }
    }
    // From outside the data, "embree" stays Embree's.
    bool tookExact = true;
    raytrace(sceneFor(Transparency::Opaque, true, 1.0f, false), lines, cameraAt({0.0f, 0.1f, 6.0f}), w, h, nullptr,
             &tookExact);
    EXPECT_FALSE(tookExact);
}

// Transparent: alpha to RGBA8 quantisation, colour within 2/255 (Embree's geometric normal vs the
// exact cone normal, the segment a joint point is attributed to), outside a few rim pixels.
struct TransparentDiff {
    int covered = 0, outside = 0;
    float maxAlpha = 0, maxColor = 0;
};

TransparentDiff compareTransparent(const FrameImages& rt, const FrameImages& ref) {
    TransparentDiff d;
    for (std::size_t i = 0; i < ref.pixelCount(); ++i) {
        d.covered += ref.rgba[4 * i + 3] > 0.0f;
        const float da = std::abs(rt.rgba[4 * i + 3] - ref.rgba[4 * i + 3]);
        float dc = 0;
        for (int c = 0; c < 3; ++c) dc = std::max(dc, std::abs(rt.rgba[4 * i + c] - ref.rgba[4 * i + c]));
        if (da > 0.5f / 255.0f || dc > 2.0f / 255.0f) {
            ++d.outside;
            continue;
        }
        d.maxAlpha = std::max(d.maxAlpha, da);
        d.maxColor = std::max(d.maxColor, dc);
    }
    return d;
}

TEST(Raytraced, exact_transparent_equals_the_transparent_reference_with_cap_clipping) {
    LightingSpec light;
    const int w = 64, h = 48;
    int covered = 0, outside = 0;
    for (unsigned seed : {4u, 5u}) {
        // Constant radius per polyline: where cap clipping tiles the union exactly
        // (core/cap_clipping.h), i.e. where "one entry per tube crossing" is the same rule.
        StyledLines lines = makeLines(randomPolylines(seed, 10, true, 0.2f, 0.7f));
        Camera cam = cameraAt({0.5f, -0.6f, 3.0f});
        FrameImages rt = raytrace(sceneFor(Transparency::DepthPeeling, true), lines, cam, w, h);
        FrameImages ref = renderReferenceTransparent(lines, cam, light, w, h, true);
        TransparentDiff d = compareTransparent(rt, ref);
        covered += d.covered;
        outside += d.outside;
    }
    EXPECT_GT(covered, 1500);
    EXPECT_LE(outside, covered / 100) << outside << " of " << covered;
}

TEST(Raytraced, exact_transparent_equals_the_transparent_reference_without_cap_clipping) {
    LightingSpec light;
    const int w = 64, h = 48;
    // Varying radii: without cap clipping every rounded cone is entered on its own (joint beads).
    StyledLines lines = makeLines(randomPolylines(6u, 10, false, 0.2f, 0.7f));
    Camera cam = cameraAt({-0.4f, 0.5f, 3.0f});
    FrameImages rt = raytrace(sceneFor(Transparency::KBuffer, false), lines, cam, w, h);
    FrameImages ref = renderReferenceTransparent(lines, cam, light, w, h, false);
    TransparentDiff d = compareTransparent(rt, ref);
    EXPECT_GT(d.covered, 700);
    EXPECT_LE(d.outside, d.covered / 100) << d.outside << " of " << d.covered;
}

TEST(Raytraced, exact_transparent_composites_more_layers_than_one_traversal_holds) {
    // 70 thin tubes stacked along the view axis: one ray crosses all 70 (more than the hits one
    // Embree traversal collects), so the result needs the multi-pass continuation to be exact.
    std::vector<PolylineSpec> pls;
    for (int k = 0; k < 70; ++k) {
        const float z = -1.0f + 2.0f * float(k) / 69.0f;
        const float a = 0.03f + 0.002f * float(k % 7);
        pls.push_back({{{-0.8f, -0.1f + 0.002f * k, z, 0.3f}, {0.8f, 0.1f - 0.002f * k, z, 0.3f}},
                       {0.2f + 0.01f * k, 0.5f, 0.9f - 0.01f * k, a},
                       {0.9f, 0.3f, 0.1f, a}});
    }
    StyledLines lines = makeLines(pls);
    LightingSpec light;
    Camera cam = cameraAt({0.0f, 0.0f, 3.0f}, Projection::Orthographic);
    const int w = 32, h = 24;
    std::vector<int> counts;
    FrameImages ref = renderReferenceTransparent(lines, cam, light, w, h, true, &counts);
    EXPECT_EQ(*std::max_element(counts.begin(), counts.end()), 70);
    FrameImages rt = raytrace(sceneFor(Transparency::DepthPeeling, true), lines, cam, w, h);
    TransparentDiff d = compareTransparent(rt, ref);
    EXPECT_EQ(d.outside, 0);
    EXPECT_LT(d.maxColor, 1e-3f);
}

TEST(Raytraced, opaque_images_are_identical_with_single_rays_packets_and_streams) {
    StyledLines lines = makeLines(randomPolylines(4u, 10, false, 1.0f, 1.0f));
    // 61 x 45: partial tiles at the right and bottom edges (masked packet lanes, short streams).
    const int w = 61, h = 45;
    for (bool exactSurface : {true, false})
        for (Projection projection : {Projection::Perspective, Projection::Orthographic}) {
            Scene scene = sceneFor(Transparency::Opaque, true, 1.0f, exactSurface);
            Camera cam = cameraAt({0.5f, 0.6f, 3.0f}, projection);
            auto r = rt::RaytracedRenderer::create(scene, lines);
            std::vector<FrameImages> images;
            for (rt::Traversal t :
                 {rt::Traversal::Single, rt::Traversal::Packet8, rt::Traversal::Packet16, rt::Traversal::Stream}) {
                r->setTraversal(t);
                FrameImages img;
                tc::CpuStageTimer timer;
                r->render(cam, w, h, img, timer);
                images.push_back(std::move(img));
            }
            int covered = 0;
            for (std::uint32_t id : images[0].id) covered += id != kBackgroundId;
            EXPECT_GT(covered, w * h / 10);
            for (int k = 1; k < 4; ++k) {
                EXPECT_EQ(images[k].rgba, images[0].rgba) << k;
                EXPECT_EQ(images[k].depth, images[0].depth) << k;
                EXPECT_EQ(images[k].normal, images[0].normal) << k;
                EXPECT_EQ(images[k].id, images[0].id) << k;
            }
        }
}

// One 40x32 frame of `r` per number of hits per traversal (1, 3, the default, the most), and the
// Embree hits each took.
struct PerHitsPerPass {
    std::vector<FrameImages> images;
    std::vector<std::uint64_t> hits;
};
PerHitsPerPass renderPerHitsPerPass(rt::RaytracedRenderer& r, const Camera& cam) {
    PerHitsPerPass out;
    for (int k : {1, 3, 0, rt::kMaxHitsPerPass}) {
        r.setHitsPerPass(k);
        FrameImages img;
        tc::CpuStageTimer timer;
        r.render(cam, 40, 32, img, timer);
        out.images.push_back(std::move(img));
        out.hits.push_back(r.lastHitCount());
    }
    return out;
}

TEST(Raytraced, transparent_images_are_identical_for_every_number_of_hits_per_traversal) {
    // The 70 stacked tubes of the test above (up to 70 entries and exits per ray) and bent tubes
    // without cap clipping (joint beads): one hit per traversal, a few, the default and the most
    // must composite the same hits in the same order, cut off or exact.
    std::vector<PolylineSpec> stack;
    for (int k = 0; k < 70; ++k) {
        const float z = -1.0f + 2.0f * float(k) / 69.0f;
        const float a = 0.05f + 0.01f * float(k % 7);
        stack.push_back({{{-0.8f, -0.1f + 0.002f * k, z, 0.3f}, {0.8f, 0.1f - 0.002f * k, z, 0.3f}},
                         {0.2f + 0.01f * k, 0.5f, 0.9f - 0.01f * k, a},
                         {0.9f, 0.3f, 0.1f, a}});
    }
    const StyledLines stacked = makeLines(stack), bent = makeLines(randomPolylines(9u, 12, false, 0.2f, 0.6f));
    for (const StyledLines* lines : {&stacked, &bent})
        for (float cutoff : {0.99f, 1.0f}) {
            auto r =
                rt::RaytracedRenderer::create(sceneFor(Transparency::DepthPeeling, lines == &stacked, cutoff), *lines);
            const auto [images, hits] = renderPerHitsPerPass(*r, cameraAt({0.1f, 0.2f, 3.0f}));
            ASSERT_GT(hits[0], 40u * 32u) << "most pixels see several hits";
            for (std::size_t k = 1; k < images.size(); ++k) {
                EXPECT_EQ(images[k].rgba, images[0].rgba) << k;
                EXPECT_EQ(images[k].depth, images[0].depth) << k;
                EXPECT_EQ(images[k].normal, images[0].normal) << k;
                EXPECT_EQ(images[k].id, images[0].id) << k;
                EXPECT_EQ(hits[k], hits[0]) << k;
            }
        }
}

// style.halo (core/halo.h): the ray tracer's halo fragments are the CPU reference's, composited in
// the same order, so images agree to float rounding except at the ring's outer rim, where Embree's
// grown curve and the exact intersector may decide a grazing ray differently.
Scene haloScene(bool capClipping, float cutoff = 1.0f) {
    Scene s = sceneFor(Transparency::DepthPeeling, capClipping, cutoff);
    s.style.halo.enabled = true;
    s.style.halo.width = 0.8f;
    s.style.halo.depth = 3.0f;
    s.style.halo.color = glm::vec3(0.9f, 0.6f, 0.1f);
    return s;
}

TEST(Raytraced, halos_equal_the_transparent_reference_with_halos) {
    LightingSpec light;
    const int w = 64, h = 48;
    for (bool clip : {true, false})
        for (float alphaLo : {0.2f, 1.0f}) {
            const std::string label = std::string(clip ? "cap clipping" : "no cap clipping") + ", alpha " +
                                      (alphaLo < 1.0f ? "0.2-0.7" : "1");
            SCOPED_TRACE(label);
            const Scene scene = haloScene(clip);
            const LineHalo halo = lineHalo(scene.style.halo, scene.image.background);
            int covered = 0, outside = 0, ringPixels = 0;
            for (Projection projection : {Projection::Perspective, Projection::Orthographic}) {
                const StyledLines lines =
                    makeLines(randomPolylines(11u, 9, clip, alphaLo, alphaLo < 1.0f ? 0.7f : 1.0f));
                const Camera cam = cameraAt({0.4f, -0.5f, 3.0f}, projection);
                const FrameImages rt = raytrace(scene, lines, cam, w, h);
                const FrameImages ref = renderReferenceTransparent(lines, cam, light, w, h, clip, nullptr, &halo);
                const FrameImages plain = renderReferenceTransparent(lines, cam, light, w, h, clip);
                const TransparentDiff d = compareTransparent(rt, ref);
                covered += d.covered;
                outside += d.outside;
                EXPECT_LE(d.maxColor, 1e-5f);
                EXPECT_LE(d.maxAlpha, 1e-6f);
                for (std::size_t i = 0; i < ref.pixelCount(); ++i) {
                    ringPixels += ref.rgba[4 * i + 3] > plain.rgba[4 * i + 3] + 0.05f;
                    if (ref.id[i] == rt.id[i] && ref.id[i] != kBackgroundId) {
                        EXPECT_NEAR(rt.depth[i], ref.depth[i], 1e-5f * ref.depth[i]) << i;
                    }
                }
            }
            std::printf("[ measured ] halos, %s: %d covered px, %d outside the tolerance, %d px with a ring\n",
                        label.c_str(), covered, outside, ringPixels);
            // Not vacuous: the rings cover many pixels the tubes alone leave (more) transparent.
            EXPECT_GT(ringPixels, 300) << label;
            EXPECT_GT(covered, 2000) << label;
            EXPECT_LE(outside, covered / 100) << outside << " of " << covered;
        }
}

TEST(Raytraced, halos_seen_from_inside_a_ring_equal_the_reference) {
    // The eye lies between a tube's surface and its ring's outer edge: rays start inside that
    // grown cone, whose exit names the segment (every fragment waits for the last hit). The
    // tube runs across the view just below the eye; random tubes lie beyond.
    LightingSpec light;
    const int w = 64, h = 48;
    std::vector<PolylineSpec> pls = randomPolylines(13u, 6, true, 0.3f, 0.6f);
    pls.push_back({{{-1.5f, -0.06f, 3.0f, 0.04f}, {0.0f, -0.06f, 3.0f, 0.04f}, {1.5f, -0.06f, 3.0f, 0.04f}},
                   {0.9f, 0.2f, 0.2f, 0.5f},
                   {0.2f, 0.9f, 0.2f, 0.5f}});
    const StyledLines lines = makeLines(pls);
    const Scene scene = haloScene(true);  // ring 0.8 radii: the eye is 0.06 from the axis, < 0.072
    const LineHalo halo = lineHalo(scene.style.halo, scene.image.background);
    const Camera cam = cameraAt({0.0f, 0.0f, 3.0f});
    const FrameImages rt = raytrace(scene, lines, cam, w, h);
    const FrameImages ref = renderReferenceTransparent(lines, cam, light, w, h, true, nullptr, &halo);
    const TransparentDiff d = compareTransparent(rt, ref);
    // The near tube and its ring cover the lower half of the image.
    EXPECT_GT(d.covered, w * h / 2);
    EXPECT_LE(d.outside, d.covered / 100) << d.outside << " of " << d.covered;
    EXPECT_LE(d.maxColor, 1e-5f);
}

TEST(Raytraced, halo_images_are_identical_for_every_number_of_hits_per_traversal) {
    // A ring's fragment lies behind the hit that names it and a tube's behind its ring's entry, so
    // fragments arrive out of depth order: one hit per traversal must composite what several or all
    // hits per traversal do.
    const StyledLines lines = makeLines(randomPolylines(12u, 14, true, 0.2f, 0.6f));
    for (float cutoff : {0.99f, 1.0f}) {
        auto r = rt::RaytracedRenderer::create(haloScene(true, cutoff), lines);
        const std::vector<FrameImages> images = renderPerHitsPerPass(*r, cameraAt({0.1f, 0.2f, 3.0f})).images;
        for (std::size_t k = 1; k < images.size(); ++k) {
            EXPECT_EQ(images[k].rgba, images[0].rgba) << k;
            EXPECT_EQ(images[k].depth, images[0].depth) << k;
            EXPECT_EQ(images[k].id, images[0].id) << k;
        }
    }
}

TEST(Raytraced, hits_per_traversal_cover_the_layers_the_alpha_cutoff_needs) {
    // 1 - 0.7^13 >= 0.99 > 1 - 0.7^12: 13 layers, each entered and left.
    EXPECT_EQ(rt::hitsPerPass(0.99f, 0.3f), 2 * 13 + 2);
    EXPECT_EQ(rt::hitsPerPass(0.99f, 0.6f), 2 * 6 + 2);
    // Few layers: one hit per traversal.
    EXPECT_EQ(rt::hitsPerPass(0.99f, 0.8f), 1);
    EXPECT_EQ(rt::hitsPerPass(0.99f, 1.0f), 1);
    EXPECT_EQ(rt::hitsPerPass(0.99f, 0.05f), rt::kMaxHitsPerPass);
    EXPECT_EQ(rt::hitsPerPass(1.0f, 0.9f), rt::kMaxHitsPerPass);  // exact: every hit
    // The renderer takes K from its lines' mean opacity.
    auto r = rt::RaytracedRenderer::create(sceneFor(Transparency::DepthPeeling, true, 0.99f),
                                           makeLines(randomPolylines(3u, 6, true, 0.6f, 0.6f)));
    EXPECT_EQ(r->hitsPerPass(), rt::hitsPerPass(0.99f, 0.6f));
}

TEST(Raytraced, a_target_reused_across_frames_gets_the_same_image_as_a_fresh_one) {
    // The renderer does not clear its target (FrameImages::resize): every pixel must be written,
    // background ones included, or the previous frame would show through.
    StyledLines lines = makeLines(randomPolylines(6u, 10, false, 1.0f, 1.0f));
    for (Transparency t : {Transparency::Opaque, Transparency::DepthPeeling}) {
        Scene scene = sceneFor(t, true);
        scene.render.ao.enabled = t == Transparency::Opaque;
        scene.render.ao.resolution = 32;
        auto r = rt::RaytracedRenderer::create(scene, lines);
        tc::CpuStageTimer timer;
        FrameImages reused, fresh;
        r->render(cameraAt({0.2f, 0.1f, 1.5f}), 40, 32, reused, timer);  // close: most pixels covered
        r->render(cameraAt({0.5f, 0.6f, 6.0f}), 40, 32, reused, timer);  // far: mostly background
        r->render(cameraAt({0.5f, 0.6f, 6.0f}), 40, 32, fresh, timer);
        EXPECT_EQ(reused.rgba, fresh.rgba);
        EXPECT_EQ(reused.depth, fresh.depth);
        EXPECT_EQ(reused.normal, fresh.normal);
        EXPECT_EQ(reused.id, fresh.id);
        EXPECT_EQ(reused.ao, fresh.ao);
    }
}

TEST(Raytraced, writes_only_the_aovs_the_output_asks_for_and_the_same_colour) {
    // An AOV nobody reads is left empty (KeptAovs): no stale values of an earlier frame in a
    // reused target, and the colour is the same with or without the AOVs.
    StyledLines lines = makeLines(randomPolylines(6u, 10, false, 0.4f, 1.0f));
    const Camera cam = cameraAt({0.2f, 0.1f, 1.8f});
    for (Transparency t : {Transparency::Opaque, Transparency::DepthPeeling}) {
        const Scene all = sceneFor(t, true);
        const FrameImages full = raytrace(all, lines, cam, 40, 32);
        ASSERT_EQ(full.depth.size(), full.pixelCount());
        ASSERT_EQ(full.id.size(), full.pixelCount());
        FrameImages reused = full;  // a target that held every AOV in the previous frame
        for (const KeptAovs keep : {KeptAovs{false, false, false}, KeptAovs{false, false, true},
                                    KeptAovs{true, false, false}, KeptAovs{false, true, false}}) {
            Scene some = all;
            some.output.aovDepth = keep.depth;
            some.output.aovNormal = keep.normal;
            some.output.aovId = keep.id;
            auto r = rt::RaytracedRenderer::create(some, lines);
            tc::CpuStageTimer timer;
            r->render(cam, 40, 32, reused, timer);
            EXPECT_EQ(reused.rgba, full.rgba);
            EXPECT_EQ(reused.depth, keep.depth ? full.depth : std::vector<float>{});
            EXPECT_EQ(reused.normal, keep.normal ? full.normal : std::vector<float>{});
            EXPECT_EQ(reused.id, keep.id ? full.id : std::vector<std::uint32_t>{});
        }
    }
}

TEST(Raytraced, images_are_identical_with_one_and_two_threads) {
    StyledLines lines = makeLines(randomPolylines(8u, 12, false, 0.3f, 0.8f));
    Camera cam = cameraAt({0.3f, 0.3f, 3.0f});
    for (Transparency t : {Transparency::Opaque, Transparency::DepthPeeling}) {
        Scene scene = sceneFor(t, true, 0.99f);
        scene.render.ao.enabled = true;
        scene.render.ao.resolution = 32;
        std::vector<FrameImages> images;
        for (int threads : {1, 2}) {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
            images.push_back(raytrace(scene, lines, cam, 40, 32));
        }
        EXPECT_EQ(images[0].rgba, images[1].rgba);
        EXPECT_EQ(images[0].depth, images[1].depth);
        EXPECT_EQ(images[0].id, images[1].id);
        EXPECT_EQ(images[0].ao, images[1].ao);
    }
}

TEST(Raytraced, alpha_cutoff_changes_each_pixel_by_at_most_what_the_cutoff_leaves) {
    StyledLines lines = makeLines(randomPolylines(9u, 30, true, 0.6f, 0.9f));
    Camera cam = cameraAt({0.0f, 0.2f, 3.0f});
    const int w = 48, h = 40;
    std::uint64_t hitsExact = 0, hitsCut = 0;
    const float cutoff = 0.95f;
    FrameImages exact = raytrace(sceneFor(Transparency::DepthPeeling, true, 1.0f), lines, cam, w, h, &hitsExact);
    FrameImages cut = raytrace(sceneFor(Transparency::DepthPeeling, true, cutoff), lines, cam, w, h, &hitsCut);
    int stopped = 0;
    for (std::size_t i = 0; i < exact.pixelCount(); ++i) {
        const float ac = cut.rgba[4 * i + 3];
        // Behind the stop, at most (1 - ac) of colour in [0, 1] and alpha is still to come.
        const float bound = 1.0f - ac + 1e-6f;
        for (int c = 0; c < 4; ++c) EXPECT_LE(std::abs(exact.rgba[4 * i + c] - cut.rgba[4 * i + c]), bound) << i;
        if (ac >= cutoff) {
            EXPECT_LE(1.0f - ac, 1.0f - cutoff + 1e-6f);
            stopped += exact.rgba[4 * i + 3] != ac;
        }
    }
    EXPECT_GT(stopped, 50);         // the cutoff really stopped rays early...
    EXPECT_LT(hitsCut, hitsExact);  // ...and saved work
}

TEST(Raytraced, density_pyramid_levels_keep_the_mean_and_an_isolated_tube_has_no_ambient_occlusion) {
    StyledLines lines =
        makeLines({{{{-0.8f, 0.0f, 0.0f, 0.04f}, {0.8f, 0.05f, 0.02f, 0.04f}}, {1, 1, 1, 1}, {1, 1, 1, 1}}});
    AoSpec spec;
    spec.enabled = true;
    spec.resolution = 48;
    rt::ConeTracedAo ao(spec, lines);
    const rt::DensityPyramid& v = ao.volume();
    ASSERT_GT(v.levels(), 3);
    // Mean over uniformly spaced sample points of each level, via sampleLevel at texel centres.
    auto levelMean = [&](int level) {
        glm::ivec3 s = v.levelSize(level);
        double sum = 0;
        for (int z = 0; z < s.z; ++z)
            for (int y = 0; y < s.y; ++y)
                for (int x = 0; x < s.x; ++x) sum += v.sampleLevel((glm::vec3(x, y, z) + 0.5f) / glm::vec3(s), level);
        return sum * std::pow(2.0, 3.0 * level);  // texel volume in level-0 voxels (even sizes)
    };
    const double total0 = levelMean(0);
    EXPECT_GT(total0, 0.0);
    // 48 -> 24 -> 12 -> 6 along x; the other axes are fitted and may be odd (weights differ).
    if (v.levelSize(0) == 2 * v.levelSize(1)) {
        EXPECT_NEAR(levelMean(1), total0, 1e-3 * total0);
    }
    // On the tube's surface, facing away from nothing: the shader's own-tube exclusion removes the
    // tube from every read. It is exact where a level's texels are whole voxels of the level below
    // (even sizes: the GL tests' 64^3 grids read exactly 1); this grid is 48 voxels long and a few
    // wide around one thin tube, and where an odd size is halved the mip shares a voxel between two
    // texels, so part of the deposit lands outside the texel the line is clipped to. Measured
    // 0.972 / 0.979 / 1.0 for the three normals.
    for (glm::vec3 n : {glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), glm::normalize(glm::vec3(0, 1, -1))}) {
        glm::vec3 p = glm::vec3(0.0f, 0.025f, 0.01f) + 0.04f * n;
        EXPECT_NEAR(ao.visibility(p, n, 0, 0), 1.0f, 0.05f);
    }
}

TEST(Raytraced, ambient_occlusion_darkens_a_bundle_with_both_methods_and_is_deterministic) {
    // 5 x 5 parallel tubes: the centre one is occluded from every side, an isolated one is not.
    std::vector<PolylineSpec> pls;
    for (int i = -2; i <= 2; ++i)
        for (int j = -2; j <= 2; ++j)
            pls.push_back(
                {{{-0.6f, 0.1f * i, 0.1f * j, 0.04f}, {0.6f, 0.1f * i, 0.1f * j, 0.04f}}, {1, 1, 1, 1}, {1, 1, 1, 1}});
    pls.push_back({{{-0.6f, 2.0f, 0.0f, 0.04f}, {0.6f, 2.0f, 0.0f, 0.04f}}, {1, 1, 1, 1}, {1, 1, 1, 1}});
    StyledLines lines = makeLines(pls);
    for (AoSpec::Method method : {AoSpec::Method::ConeTraced, AoSpec::Method::RayTraced}) {
        Scene scene = sceneFor(Transparency::Opaque, true);
        scene.render.ao.enabled = true;
        scene.render.ao.method = method;
        scene.render.ao.resolution = 64;
        scene.render.ao.samples = 16;
        // Looking down -z at the centre tube's top (between its neighbours) and at the lone tube.
        Camera cam = cameraAt({0.0f, 1.0f, 4.0f}, Projection::Orthographic);
        cam.target = {0.0f, 1.0f, 0.0f};
        cam.orthoHeight = 2.4f;
        const int w = 40, h = 40;
        FrameImages a = raytrace(scene, lines, cam, w, h);
        FrameImages b = raytrace(scene, lines, cam, w, h);
        EXPECT_EQ(a.ao, b.ao);
        float lone = 0.0f;
        for (std::size_t i = 0; i < a.pixelCount(); ++i)
            if (a.id[i] == 25) lone = std::max(lone, a.ao[i]);
        EXPECT_GT(lone, 0.99f) << int(method);
        // The front layer of the bundle (j = 2, facing the camera) still has tubes behind and beside it.
        float frontMean = 0;
        int frontCount = 0;
        for (std::size_t i = 0; i < a.pixelCount(); ++i)
            if (a.id[i] != kBackgroundId && a.id[i] < 25 && a.id[i] % 5 == 4) frontMean += a.ao[i], ++frontCount;
        ASSERT_GT(frontCount, 0);
        EXPECT_LT(frontMean / float(frontCount), 0.95f) << int(method);
    }
}

}  // namespace
}  // namespace tc
