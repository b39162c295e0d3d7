// The k-d decomposition of data-parallel rendering: regions tile space, the tree splits at the
// quantiles, the view order is one no ray contradicts, every segment and sphere is assigned to
// every region it reaches, a region's extracted line set clips its joints like the whole set,
// and the tree survives a save/load round trip.
#include "core/kd_decomposition.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "core/cap_clipping.h"
#include "core/error.h"
#include "core/generators.h"
#include "core/rounded_cone.h"
#include "core/styling.h"

namespace tc {
namespace {

std::vector<glm::vec3> randomPoints(std::size_t n, std::uint32_t seed, float scale = 1.0f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-scale, scale);
    std::vector<glm::vec3> points(n);
    // Anisotropic on purpose, so the longest axis changes between levels.
    for (glm::vec3& p : points) p = {2.0f * u(rng), u(rng), 0.5f * u(rng)};
    return points;
}

glm::vec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> n;
    glm::vec3 v{n(rng), n(rng), n(rng)};
    return glm::normalize(v);
}

// Random polylines with random per-vertex radii and one attribute.
LineSet randomLines(int polylines, int segments, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    LineSet lines;
    lines.attributes.push_back({"a", {}});
    for (int p = 0; p < polylines; ++p) {
        glm::vec3 x{2.0f * u(rng), u(rng), u(rng)};
        for (int i = 0; i <= segments; ++i) {
            lines.positions.push_back(x);
            lines.attributes[0].values.push_back(float(lines.positions.size()));
            x += 0.08f * randomUnit(rng);
        }
        lines.offsets.push_back(std::uint32_t(lines.positions.size()));
    }
    cleanLineSet(lines);
    return lines;
}

int containingBoxes(const KdDecomposition& tree, const glm::vec3& p) {
    int n = 0;
    for (const RegionBox& b : tree.boxes()) n += b.contains(p);
    return n;
}

TEST(KdDecomposition, one_region_tree_is_the_unbounded_box) {
    EXPECT_EQ(KdDecomposition().regionCount(), 1);
    EXPECT_TRUE(KdDecomposition().box(0).unbounded());
    const KdDecomposition tree = KdDecomposition::build(randomPoints(100, 1), 1);
    ASSERT_EQ(tree.regionCount(), 1);
    EXPECT_TRUE(tree.box(0).unbounded());
    EXPECT_EQ(tree.viewOrderFromPosition({1, 2, 3}), std::vector<int>{0});
    EXPECT_EQ(tree.regionOf({1e30f, -1e30f, 0}), 0);
}

TEST(KdDecomposition, regions_are_disjoint_and_cover_space) {
    const std::vector<glm::vec3> points = randomPoints(2000, 2);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    for (int n : {2, 3, 5, 7, 8, 13, 64}) {
        const KdDecomposition tree = KdDecomposition::build(points, n);
        ASSERT_EQ(tree.regionCount(), n);
        ASSERT_EQ(tree.nodes().size(), std::size_t(2 * n - 1));
        // Random points in and far around the data, the data points themselves, and points ON
        // every split plane (where a half-open box must still claim exactly one of the two sides).
        std::vector<glm::vec3> probes = points;
        for (int i = 0; i < 4000; ++i) probes.push_back({u(rng), u(rng), u(rng)});
        for (const KdNode& node : tree.nodes())
            if (!node.leaf())
                for (int i = 0; i < 50; ++i) {
                    glm::vec3 p{u(rng), u(rng), u(rng)};
                    p[node.axis] = node.split;
                    probes.push_back(p);
                }
        probes.push_back(glm::vec3(std::numeric_limits<float>::max()));
        probes.push_back(glm::vec3(-std::numeric_limits<float>::max()));
        for (const glm::vec3& p : probes) {
            ASSERT_EQ(containingBoxes(tree, p), 1) << n << " regions, point " << p.x << " " << p.y << " " << p.z;
            EXPECT_TRUE(tree.box(tree.regionOf(p)).contains(p));
        }
        // Outermost faces are infinite: the union of the boxes is all of space.
        int infiniteFaces = 0;
        for (const RegionBox& b : tree.boxes())
            for (int a = 0; a < 3; ++a) infiniteFaces += std::isinf(b.lo[a]) + std::isinf(b.hi[a]);
        EXPECT_GE(infiniteFaces, 6);
    }
}

TEST(KdDecomposition, splits_are_at_the_region_quantile_and_leaves_are_balanced) {
    const std::vector<glm::vec3> points = randomPoints(10007, 4);
    for (int n : {2, 3, 5, 6, 7, 12, 31}) {
        const KdDecomposition tree = KdDecomposition::build(points, n);
        std::vector<std::size_t> perRegion(std::size_t(n), 0);
        for (const glm::vec3& p : points) ++perRegion[std::size_t(tree.regionOf(p))];
        // Points and regions per subtree.
        const auto& nodes = tree.nodes();
        std::vector<std::size_t> count(nodes.size(), 0), regions(nodes.size(), 0);
        for (std::size_t i = nodes.size(); i-- > 0;) {  // children come after their parent
            if (nodes[i].leaf()) {
                count[i] = perRegion[std::size_t(nodes[i].region)];
                regions[i] = 1;
            } else {
                count[i] = count[std::size_t(nodes[i].lower)] + count[std::size_t(nodes[i].upper)];
                regions[i] = regions[std::size_t(nodes[i].lower)] + regions[std::size_t(nodes[i].upper)];
            }
        }
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            if (nodes[i].leaf()) continue;
            // floor(n/2) regions below, ceil(n/2) above; with distinct coordinates (random floats)
            // the lower side holds exactly the rounded quantile count.
            EXPECT_EQ(regions[std::size_t(nodes[i].lower)], regions[i] / 2);
            EXPECT_EQ(count[std::size_t(nodes[i].lower)],
                      std::size_t(std::llround(double(count[i]) * double(regions[i] / 2) / double(regions[i]))))
                << n << " regions, node " << i;
        }
        // Rounding at every level adds at most 1/2 point, scaled down by the child's share (<= 2/3)
        // on the way: every region is within 1.5 points of the mean.
        const double mean = double(points.size()) / n;
        for (std::size_t c : perRegion) EXPECT_LT(std::abs(double(c) - mean), 1.5) << n << " regions";
    }
}

TEST(KdDecomposition, tied_coordinates_and_more_regions_than_points_still_tile_space) {
    std::vector<glm::vec3> same(50, glm::vec3(0.25f, -1.0f, 2.0f));
    same.push_back({0.25f, -1.0f, 3.0f});
    for (const auto& points : {same, std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}}, std::vector<glm::vec3>{}}) {
        const KdDecomposition tree = KdDecomposition::build(points, 5);
        ASSERT_EQ(tree.regionCount(), 5);
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(-4.0f, 4.0f);
        for (int i = 0; i < 2000; ++i) {
            const glm::vec3 p{u(rng), u(rng), u(rng)};
            ASSERT_EQ(containingBoxes(tree, p), 1);
        }
        for (const glm::vec3& p : points) ASSERT_EQ(containingBoxes(tree, p), 1);
    }
}

TEST(KdDecomposition, build_is_deterministic_and_independent_of_point_order) {
    std::vector<glm::vec3> points = randomPoints(200000, 6);  // large enough to build in parallel
    const KdDecomposition a = KdDecomposition::build(points, 11);
    std::shuffle(points.begin(), points.end(), std::mt19937(7));
    const KdDecomposition b = KdDecomposition::build(points, 11);
    EXPECT_TRUE(a == b);
    EXPECT_EQ(a.boxes(), b.boxes());
    EXPECT_FALSE(a == KdDecomposition::build(points, 10));
}

// Walks rays in small steps and checks that the regions they pass through come in the view
// order: the position of the region in the order never decreases.
void expectRaysFollowOrder(const KdDecomposition& tree, const std::vector<int>& order, glm::vec3 origin, glm::vec3 dir,
                           float t0, float t1, int steps) {
    std::vector<int> rank(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) rank[std::size_t(order[i])] = int(i);
    int previous = -1;
    for (int i = 0; i <= steps; ++i) {
        const float t = t0 + (t1 - t0) * float(i) / float(steps);
        const int r = rank[std::size_t(tree.regionOf(origin + t * dir))];
        ASSERT_GE(r, previous) << "ray from " << origin.x << " " << origin.y << " " << origin.z << " dir " << dir.x
                               << " " << dir.y << " " << dir.z << " goes back from region "
                               << order[std::size_t(previous)] << " to " << order[std::size_t(r)] << " at t = " << t;
        previous = r;
    }
}

TEST(KdDecomposition, no_ray_visits_regions_against_the_view_order) {
    const KdDecomposition tree = KdDecomposition::build(randomPoints(3000, 8), 9);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    for (int e = 0; e < 40; ++e) {
        // Perspective: eyes inside and outside the data; rays leave the eye (t >= 0).
        const glm::vec3 eye{u(rng), u(rng), u(rng)};
        const std::vector<int> order = tree.viewOrderFromPosition(eye);
        std::vector<int> sorted = order;
        std::sort(sorted.begin(), sorted.end());
        for (int i = 0; i < 9; ++i) ASSERT_EQ(sorted[std::size_t(i)], i);  // each region once
        for (int r = 0; r < 50; ++r) expectRaysFollowOrder(tree, order, eye, randomUnit(rng), 0.0f, 12.0f, 2000);

        // Orthographic: parallel rays along one direction, from anywhere (whole lines).
        const glm::vec3 dir = randomUnit(rng);
        const std::vector<int> parallel = tree.viewOrderInDirection(dir);
        for (int r = 0; r < 50; ++r)
            expectRaysFollowOrder(tree, parallel, {u(rng), u(rng), u(rng)}, dir, -12.0f, 12.0f, 3000);
    }
    // viewOrder(camera) picks the rule by projection.
    Camera camera;
    camera.eye = {0.3f, -2.0f, 5.0f};
    EXPECT_EQ(tree.viewOrder(camera), tree.viewOrderFromPosition(camera.eye));
    camera.projection = Projection::Orthographic;
    EXPECT_EQ(tree.viewOrder(camera), tree.viewOrderInDirection(camera.forward()));
}

bool assigned(const RegionItems& items, int region, std::uint32_t i) {
    const auto& list = items[std::size_t(region)];
    return std::binary_search(list.begin(), list.end(), i);
}

TEST(KdDecomposition, every_segment_is_assigned_to_every_region_its_rounded_cone_reaches) {
    const LineSet lines = randomLines(60, 40, 10);
    const KdDecomposition tree = KdDecomposition::build(segmentMidpoints(lines), 7);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> radii(lines.vertexCount());
    for (float& r : radii) r = 0.01f + 0.05f * u(rng);
    const RegionItems items = assignSegments(tree, lines, radii);
    for (const auto& list : items) EXPECT_TRUE(std::is_sorted(list.begin(), list.end()));

    std::size_t total = 0, owned = 0;
    for (const auto& list : items) total += list.size();
    for (std::size_t p = 0; p < lines.polylineCount(); ++p)
        for (std::uint32_t v = lines.offsets[p]; v + 1 < lines.offsets[p + 1]; ++v) {
            const std::uint32_t s = std::uint32_t(v - p);
            const RoundedCone cone{lines.positions[v], radii[v], lines.positions[v + 1], radii[v + 1]};
            // The rounded cone is the union of the spheres interpolated between its end spheres
            // (the convex hull of two balls): points on those spheres cover its whole surface.
            for (int i = 0; i < 200; ++i) {
                const float w = u(rng);
                const glm::vec3 p = glm::mix(cone.x0, cone.x1, w) + glm::mix(cone.r0, cone.r1, w) * randomUnit(rng);
                ASSERT_TRUE(assigned(items, tree.regionOf(p), s)) << "segment " << s;
            }
            // Entry points of rays at the cone, as a renderer computes them in float.
            for (int i = 0; i < 40; ++i) {
                const glm::vec3 target = glm::mix(cone.x0, cone.x1, u(rng)) + 0.9f * cone.r0 * randomUnit(rng);
                const glm::vec3 origin = target + 3.0f * randomUnit(rng);
                const Ray ray{origin, glm::normalize(target - origin)};
                const ConeInterval hit = intersectRoundedCone(ray, cone);
                if (hit.hit) {
                    ASSERT_TRUE(assigned(items, tree.regionOf(ray.origin + hit.tIn * ray.dir), s));
                }
            }
            // The owner (region of the midpoint) is one of the assigned regions.
            const int owner = tree.regionOf(segmentMidpoint(cone.x0, cone.x1));
            EXPECT_TRUE(assigned(items, owner, s));
        }
    for (int r = 0; r < tree.regionCount(); ++r) owned += ownedSegments(tree, r, lines).size();
    EXPECT_EQ(owned, lines.segmentCount());  // each segment owned exactly once
    // Not everything everywhere: with these radii a segment reaches few of the 7 regions.
    EXPECT_LT(total, 2 * lines.segmentCount());
    EXPECT_GT(total, lines.segmentCount());  // but some cross boundaries
}

TEST(KdDecomposition, uniform_radius_assignment_matches_per_vertex_radii) {
    const LineSet lines = randomLines(30, 30, 12);
    const KdDecomposition tree = KdDecomposition::build(segmentMidpoints(lines), 5);
    const std::vector<float> radii(lines.vertexCount(), 0.03f);
    EXPECT_EQ(assignSegments(tree, lines, 0.03f), assignSegments(tree, lines, radii));
    // Larger tubes reach more regions.
    std::size_t thin = 0, thick = 0;
    for (const auto& l : assignSegments(tree, lines, 0.001f)) thin += l.size();
    for (const auto& l : assignSegments(tree, lines, 0.3f)) thick += l.size();
    EXPECT_LT(thin, thick);
}

TEST(KdDecomposition, every_particle_is_assigned_to_every_region_its_sphere_reaches) {
    ParticleSet particles;
    particles.positions = randomPoints(3000, 13);
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (std::size_t i = 0; i < particles.size(); ++i) particles.radii.push_back(0.02f + 0.1f * u(rng));
    particles.attributes.push_back({"id", {}});
    for (std::size_t i = 0; i < particles.size(); ++i) particles.attributes[0].values.push_back(float(i));
    particles.update();

    const KdDecomposition tree = KdDecomposition::build(particles.positions, 6);
    const RegionItems items = assignParticles(tree, particles, particles.radii);
    std::size_t owned = 0;
    for (std::uint32_t i = 0; i < particles.size(); ++i)
        for (int k = 0; k < 30; ++k) {
            const glm::vec3 p = particles.positions[i] + particles.radii[i] * randomUnit(rng);
            ASSERT_TRUE(assigned(items, tree.regionOf(p), i));
        }
    for (int r = 0; r < 6; ++r) {
        const std::vector<std::uint32_t> own = ownedParticles(tree, r, particles);
        owned += own.size();
        for (std::uint32_t i : own) EXPECT_TRUE(assigned(items, r, i));
        // The extracted set is the assigned particles with their radii and attributes.
        const ParticleSet sub = extractParticles(particles, items[std::size_t(r)]);
        ASSERT_EQ(sub.size(), items[std::size_t(r)].size());
        for (std::size_t j = 0; j < sub.size(); ++j) {
            const std::uint32_t i = items[std::size_t(r)][j];
            EXPECT_EQ(sub.positions[j], particles.positions[i]);
            EXPECT_EQ(sub.radii[j], particles.radii[i]);
            EXPECT_EQ(sub.attributes[0].values[j], float(i));
        }
        EXPECT_EQ(sub.attributes[0].min, particles.attributes[0].min);  // the source's range
        EXPECT_EQ(sub.attributes[0].max, particles.attributes[0].max);
        EXPECT_NO_THROW(sub.checkConsistent());
    }
    EXPECT_EQ(owned, particles.size());
}

TEST(KdDecomposition, extracted_runs_hold_the_assigned_segments_and_one_neighbour_each_way) {
    const LineSet lines = randomLines(40, 60, 15);
    const KdDecomposition tree = KdDecomposition::build(segmentMidpoints(lines), 6);
    const RegionItems items = assignSegments(tree, lines, 0.02f);
    auto isAssigned = [&](int r, std::size_t v) {  // the segment starting at source vertex v
        std::size_t p =
            std::size_t(std::upper_bound(lines.offsets.begin(), lines.offsets.end(), v) - lines.offsets.begin()) - 1;
        return assigned(items, r, std::uint32_t(v - p));
    };
    for (int r = 0; r < 6; ++r) {
        const RegionLines sub = extractRegionLines(lines, items[std::size_t(r)]);
        ASSERT_EQ(sub.origins.size(), sub.lines.polylineCount());
        std::set<std::size_t> covered;  // source first vertices of the segments in the runs
        for (std::size_t q = 0; q < sub.lines.polylineCount(); ++q) {
            const RunOrigin o = sub.origins[q];
            const std::size_t begin = lines.offsets[o.polyline], end = lines.offsets[o.polyline + 1];
            const std::size_t first = o.firstVertex, n = sub.lines.offsets[q + 1] - sub.lines.offsets[q];
            const std::size_t last = first + n - 1;
            ASSERT_GE(first, begin);
            ASSERT_LT(last, end);
            for (std::size_t i = 0; i < n; ++i) {
                EXPECT_EQ(sub.lines.positions[sub.lines.offsets[q] + i], lines.positions[first + i]);
                EXPECT_EQ(sub.lines.attributes[0].values[sub.lines.offsets[q] + i],
                          lines.attributes[0].values[first + i]);
            }
            for (std::size_t v = first; v < last; ++v) EXPECT_TRUE(covered.insert(v).second) << "segment twice";
            // Ends: the polyline's own end, or one unassigned neighbour before an assigned segment.
            if (first > begin) {
                EXPECT_FALSE(isAssigned(r, first));
                EXPECT_TRUE(isAssigned(r, first + 1));
            }
            if (last < end - 1) {
                EXPECT_FALSE(isAssigned(r, last - 1));
                EXPECT_TRUE(isAssigned(r, last - 2));
            }
        }
        // Every assigned segment is in a run.
        for (std::size_t p = 0; p < lines.polylineCount(); ++p)
            for (std::size_t v = lines.offsets[p]; v + 1 < lines.offsets[p + 1]; ++v)
                if (isAssigned(r, v)) {
                    EXPECT_TRUE(covered.count(v)) << "region " << r << " lost segment at vertex " << v;
                }
        EXPECT_EQ(sub.lines.attributes[0].min, lines.attributes[0].min);
        EXPECT_EQ(sub.lines.attributes[0].max, lines.attributes[0].max);
    }
}

TEST(KdDecomposition, extracted_region_clips_its_assigned_segments_as_the_whole_set_does) {
    const LineSet lines = generateDataset("tornado", 30, 80, 3);
    const KdDecomposition tree = KdDecomposition::build(segmentMidpoints(lines), 5);
    const RegionItems items = assignSegments(tree, lines, 0.01f);
    StyleSpec style;
    const StyledLines whole = styleLines(lines, style, "");
    for (int r = 0; r < 5; ++r) {
        const RegionLines sub = extractRegionLines(lines, items[std::size_t(r)]);
        const StyledLines part = styleLines(sub.lines, style, "");
        std::size_t checked = 0, cut = 0;
        for (std::size_t q = 0; q < sub.lines.polylineCount(); ++q) {
            const RunOrigin o = sub.origins[q];
            const std::size_t sourceSegment0 = o.firstVertex - o.polyline;  // of the run's first vertex
            const std::size_t partSegment0 = sub.lines.offsets[q] - q;
            const std::size_t n = sub.lines.offsets[q + 1] - sub.lines.offsets[q] - 1;
            const bool cutBefore = o.firstVertex > lines.offsets[o.polyline];
            const bool cutAfter = o.firstVertex + n + 1 < lines.offsets[o.polyline + 1];
            cut += cutBefore + cutAfter;
            for (std::size_t j = 0; j < n; ++j) {
                const std::uint32_t s = std::uint32_t(sourceSegment0 + j);
                if (!assigned(items, r, s)) continue;  // a joint neighbour: its outer cap differs
                const ClipPlanes a = segmentClipPlanes(whole, s), b = segmentClipPlanes(part, partSegment0 + j);
                ASSERT_EQ(a.clip0, b.clip0);
                ASSERT_EQ(a.clip1, b.clip1);
                ASSERT_EQ(a.p0, b.p0);
                ASSERT_EQ(a.p1, b.p1);
                ++checked;
            }
        }
        EXPECT_EQ(checked, items[std::size_t(r)].size());
        EXPECT_GT(cut, 0u) << "region " << r << ": no polyline is cut, the test checks nothing at cuts";
    }
}

TEST(KdDecomposition, tree_survives_a_json_round_trip) {
    const KdDecomposition tree = KdDecomposition::build(randomPoints(5000, 16), 13);
    const nlohmann::json saved = nlohmann::json::parse(tree.toJson().dump());
    const KdDecomposition loaded = KdDecomposition::fromJson(saved, "index.json");
    EXPECT_TRUE(loaded == tree);
    EXPECT_EQ(loaded.boxes(), tree.boxes());
    EXPECT_EQ(KdDecomposition::fromJson(KdDecomposition().toJson(), "x").regionCount(), 1);
}

TEST(KdDecomposition, trees_with_any_region_numbering_load) {
    // Regions numbered against depth-first order: region 2 below x = 0, regions 0 and 1 above.
    std::vector<KdNode> nodes{{.axis = 0, .split = 0.0f, .lower = 1, .upper = 2},
                              {.region = 2},
                              {.axis = 1, .split = 1.0f, .lower = 3, .upper = 4},
                              {.region = 1},
                              {.region = 0}};
    const KdDecomposition tree = KdDecomposition::fromNodes(nodes, "t");
    EXPECT_EQ(tree.regionOf({-1, 5, 0}), 2);
    EXPECT_EQ(tree.regionOf({1, 0, 0}), 1);
    EXPECT_EQ(tree.regionOf({1, 2, 0}), 0);
    EXPECT_EQ(tree.box(1).hi.y, 1.0f);
    EXPECT_EQ(tree.viewOrderFromPosition({5, 5, 0}), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(tree.viewOrderInDirection({-1, 1, 0}), (std::vector<int>{1, 0, 2}));
    std::vector<int> regions;
    Bounds box{{-1, 0.5f, 0}, {0, 0.9f, 0}};  // touches x = 0: closed box, half-open regions
    tree.regionsOverlapping(box, regions);
    EXPECT_EQ(regions, (std::vector<int>{1, 2}));
}

std::string loadError(const nlohmann::json& tree) {
    try {
        KdDecomposition::fromJson(tree, "index.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(KdDecomposition, bad_saved_trees_are_input_errors_with_their_location) {
    nlohmann::json good = KdDecomposition::build(randomPoints(100, 17), 3).toJson();
    nlohmann::json outside = good;  // node 2 (the upper child) split below its parent's plane
    outside["nodes"][2]["axis"] = good["nodes"][0]["axis"];
    outside["nodes"][2]["split"] = good["nodes"][0]["split"].get<double>() - 1.0;
    EXPECT_NE(loadError(outside).find("index.json: tree: nodes[2]: split"), std::string::npos) << loadError(outside);
    nlohmann::json twice = good;
    twice["nodes"][1]["region"] = 2;
    EXPECT_NE(loadError(twice).find("region 2 appears twice"), std::string::npos) << loadError(twice);
    nlohmann::json count = good;
    count["regions"] = 4;
    EXPECT_NE(loadError(count).find("index.json: tree.nodes: expected an array of 7 nodes"), std::string::npos)
        << loadError(count);
    nlohmann::json axis = good;
    axis["nodes"][0]["axis"] = "w";
    EXPECT_NE(loadError(axis).find("index.json: tree.nodes[0].axis: expected one of"), std::string::npos)
        << loadError(axis);
    nlohmann::json extra = good;
    extra["nodes"][1]["colour"] = 1;
    EXPECT_NE(loadError(extra).find("tree.nodes[1]"), std::string::npos) << loadError(extra);
    nlohmann::json cycle = good;
    cycle["nodes"][0]["upper"] = 1;  // node 1 reached twice, node 2 unreachable
    EXPECT_NE(loadError(cycle).find("reached twice"), std::string::npos) << loadError(cycle);
}

}  // namespace
}  // namespace tc
