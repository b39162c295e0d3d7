#pragma once
// Data-parallel rendering without MPI, for the tests of region clipping (tests/gl/region_test.cpp,
// tests/unit/raytraced_region_test.cpp): a k-d split of space written by hand (its regions'
// boxes and their view order), the share of a line set a region's rank holds, and the two
// compositing operators of sort-last rendering done on the CPU (Z for opaque frames, "under" in
// view order for transparent ones), as IceT does them over ranks.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <vector>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/region.h"
#include "core/styled_lines.h"
#include "core/styled_particles.h"

namespace tc::test {

// A k-d tree of axis-aligned split planes. Region indices: the `lo` subtree's regions (coordinate
// < position), then the `hi` subtree's (>= position), as RegionBox is half-open.
class RegionSplit {
public:
    static RegionSplit leaf() { return RegionSplit(); }
    static RegionSplit split(int axis, float position, RegionSplit lo, RegionSplit hi) {
        RegionSplit s;
        s.m_axis = axis;
        s.m_position = position;
        s.m_lo = std::make_shared<RegionSplit>(std::move(lo));
        s.m_hi = std::make_shared<RegionSplit>(std::move(hi));
        return s;
    }

    std::size_t count() const { return m_axis < 0 ? 1 : m_lo->count() + m_hi->count(); }

    // The regions' boxes; together they tile space.
    std::vector<RegionBox> boxes() const {
        std::vector<RegionBox> out;
        collect(RegionBox{}, out);
        return out;
    }

    // Region indices front to back for `camera`: at every plane, the side the eye is on first
    // (perspective), or the side the view direction comes from (orthographic: its rays start on
    // the eye plane, which may straddle the split plane).
    std::vector<std::size_t> frontToBack(const Camera& camera) const {
        std::vector<std::size_t> out;
        order(camera, 0, out);
        return out;
    }

    // The planes (axis, position) inside the tree, for counting the segments they cut.
    void planes(std::vector<std::pair<int, float>>& out) const {
        if (m_axis < 0) return;
        out.push_back({m_axis, m_position});
        m_lo->planes(out);
        m_hi->planes(out);
    }

private:
    void collect(RegionBox box, std::vector<RegionBox>& out) const {
        if (m_axis < 0) {
            out.push_back(box);
            return;
        }
        RegionBox lo = box, hi = box;
        lo.hi[m_axis] = std::min(lo.hi[m_axis], m_position);
        hi.lo[m_axis] = std::max(hi.lo[m_axis], m_position);
        m_lo->collect(lo, out);
        m_hi->collect(hi, out);
    }
    void order(const Camera& camera, std::size_t first, std::vector<std::size_t>& out) const {
        if (m_axis < 0) {
            out.push_back(first);
            return;
        }
        const bool loFirst = camera.projection == Projection::Orthographic ? camera.forward()[m_axis] > 0.0f
                                                                           : camera.eye[m_axis] < m_position;
        const std::size_t hiFirst = first + m_lo->count();
        if (loFirst) {
            m_lo->order(camera, first, out);
            m_hi->order(camera, hiFirst, out);
        } else {
            m_hi->order(camera, hiFirst, out);
            m_lo->order(camera, first, out);
        }
    }

    int m_axis = -1;
    float m_position = 0;
    std::shared_ptr<RegionSplit> m_lo, m_hi;
};

// The closed bounds of segment s's rounded cone.
// `reach`: the radii's factor (the halo ring's, core/halo.h haloReach).
inline void segmentBounds(const StyledLines& lines, std::size_t s, glm::vec3& lo, glm::vec3& hi, float reach = 1.0f) {
    const glm::vec4 a = lines.positionRadius[lines.segmentVertices[2 * s]];
    const glm::vec4 b = lines.positionRadius[lines.segmentVertices[2 * s + 1]];
    lo = glm::min(glm::vec3(a) - reach * a.w, glm::vec3(b) - reach * b.w);
    hi = glm::max(glm::vec3(a) + reach * a.w, glm::vec3(b) + reach * b.w);
}

// How many segments' tubes reach more than one of `boxes` (cross a region face).
inline std::size_t segmentsCrossingRegions(const StyledLines& lines, const std::vector<RegionBox>& boxes) {
    std::size_t n = 0;
    for (std::size_t s = 0; s < lines.segmentCount(); ++s) {
        glm::vec3 lo, hi;
        segmentBounds(lines, s, lo, hi);
        std::size_t reached = 0;
        for (const RegionBox& b : boxes) reached += b.reaches(lo, hi) ? 1 : 0;
        n += reached > 1 ? 1 : 0;
    }
    return n;
}

// The particles whose sphere reaches `box`: what a region's rank holds of a particle set.
inline StyledParticles spheresReaching(const StyledParticles& all, const RegionBox& box) {
    StyledParticles p;
    for (std::size_t i = 0; i < all.size(); ++i) {
        const glm::vec4 cr = all.centerRadius[i];
        if (!box.reaches(glm::vec3(cr) - cr.w, glm::vec3(cr) + cr.w)) continue;
        p.centerRadius.push_back(cr);
        p.color.push_back(all.color[i]);
        p.id.push_back(all.id[i]);
        p.bounds.extend(glm::vec3(cr), cr.w);
        p.maxRadius = std::max(p.maxRadius, cr.w);
    }
    return p;
}

// What a rank of region `box` holds of `lines` (laid out as styleLines builds them: contiguous
// polylines, segments (v, v + 1)): every segment whose tube reaches the box, and each one's
// polyline neighbours, so the cap clipping planes at the ends of a kept run have their third
// vertex. Runs keep their order (segment order, hence draw-order ties, are the full set's) and
// their polyline ids; a run's end vertices are flagged First / LastOfPolyline (a neighbour added
// for its plane lies wholly outside the box, so its own cap never shows there). `reach`: as
// segmentBounds (halos: the rings reach further than the tubes).
inline StyledLines linesReaching(const StyledLines& lines, const RegionBox& box, float reach = 1.0f) {
    const std::size_t segments = lines.segmentCount();
    auto joined = [&](std::size_t s) {  // segment s continues into s + 1
        const std::uint32_t v = lines.segmentVertices[2 * s + 1];
        return s + 1 < segments && lines.segmentVertices[2 * (s + 1)] == v && !(lines.flags[v] & LastOfPolyline);
    };
    std::vector<char> reaches(segments), keep(segments);
    for (std::size_t s = 0; s < segments; ++s) {
        glm::vec3 lo, hi;
        segmentBounds(lines, s, lo, hi, reach);
        reaches[s] = box.reaches(lo, hi);
    }
    for (std::size_t s = 0; s < segments; ++s)
        keep[s] = reaches[s] || (s > 0 && joined(s - 1) && reaches[s - 1]) || (joined(s) && reaches[s + 1]);
    StyledLines out;
    for (std::size_t s = 0; s < segments; ++s) {
        if (!keep[s]) continue;
        const bool startsRun = s == 0 || !keep[s - 1] || !joined(s - 1);
        const bool endsRun = !joined(s) || !keep[s + 1];
        auto addVertex = [&](std::uint32_t v, std::uint32_t flags) {
            out.positionRadius.push_back(lines.positionRadius[v]);
            out.color.push_back(lines.color[v]);
            out.polylineId.push_back(lines.polylineId[v]);
            out.flags.push_back(flags);
            out.bounds.extend(glm::vec3(lines.positionRadius[v]), lines.positionRadius[v].w);
            out.maxRadius = std::max(out.maxRadius, lines.positionRadius[v].w);
        };
        if (startsRun) addVertex(lines.segmentVertices[2 * s], FirstOfPolyline);
        const std::uint32_t v0 = std::uint32_t(out.positionRadius.size() - 1);
        addVertex(lines.segmentVertices[2 * s + 1], endsRun ? LastOfPolyline : 0u);
        out.segmentVertices.push_back(v0);
        out.segmentVertices.push_back(v0 + 1);
    }
    return out;
}

// Covered pixels of a region's image whose first surface (from the depth AOV) lies outside its
// box by more than float rounding: a region must show only what enters the rays inside it.
inline std::size_t pixelsOutsideBox(const FrameImages& image, const Camera& camera, const RegionBox& box) {
    const PixelRays rays(camera, image.width, image.height);
    const glm::vec3 forward = camera.forward();
    std::size_t n = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(image.width) + std::size_t(x);
            if (!std::isfinite(image.depth[i])) continue;
            const Ray ray = rays(float(x), float(y));
            const float t = camera.projection == Projection::Orthographic ? image.depth[i]
                                                                          : image.depth[i] / glm::dot(ray.dir, forward);
            const glm::vec3 p = ray.origin + t * ray.dir;
            const glm::vec3 outside = glm::max(box.lo - p, glm::vec3(0.0f)) + glm::max(p - box.hi, glm::vec3(0.0f));
            n += glm::length(outside) > 1e-5f * (1.0f + std::abs(t));
        }
    return n;
}

// Z compositing of opaque regions: per pixel the region with the smallest depth (the first of
// them on a tie), all of its buffers (rgba, depth, normal, id, ao when rendered).
inline FrameImages compositeNearest(const std::vector<FrameImages>& regions) {
    FrameImages out = regions.at(0);
    for (std::size_t i = 0; i < out.pixelCount(); ++i) {
        std::size_t best = 0;
        for (std::size_t r = 1; r < regions.size(); ++r)
            if (regions[r].depth[i] < regions[best].depth[i]) best = r;
        const FrameImages& b = regions[best];
        for (int c = 0; c < 4; ++c) out.rgba[4 * i + c] = b.rgba[4 * i + c];
        for (int c = 0; c < 3; ++c) out.normal[3 * i + c] = b.normal[3 * i + c];
        out.depth[i] = b.depth[i];
        out.id[i] = b.id[i];
        if (!out.ao.empty()) out.ao[i] = b.ao[i];
    }
    return out;
}

// Ordered compositing of transparent regions: premultiplied "under" in `order` (front to back),
// C += (1 - A) c, A += (1 - A) a. The AOVs (first surface) are Z-composited.
inline FrameImages compositeUnder(const std::vector<FrameImages>& regions, const std::vector<std::size_t>& order) {
    FrameImages out = compositeNearest(regions);
    for (std::size_t i = 0; i < out.pixelCount(); ++i) {
        glm::vec4 acc(0.0f);
        for (std::size_t r : order) {
            const float* src = &regions[r].rgba[4 * i];
            const float w = 1.0f - acc.w;
            acc += glm::vec4(w * src[0], w * src[1], w * src[2], w * src[3]);
        }
        for (int c = 0; c < 4; ++c) out.rgba[4 * i + c] = acc[c];
    }
    return out;
}

// A k-d split with a name for test messages.
struct Layout {
    const char* name;
    RegionSplit split;
};

// 2, 3 and 4 regions, planes through the middle of data around the origin at uneven positions.
inline std::vector<Layout> layouts() {
    using S = RegionSplit;
    return {{"2 regions", S::split(0, 0.05f, S::leaf(), S::leaf())},
            {"3 regions", S::split(0, -0.1f, S::leaf(), S::split(1, 0.08f, S::leaf(), S::leaf()))},
            {"4 regions",
             S::split(0, 0.02f, S::split(1, -0.07f, S::leaf(), S::leaf()), S::split(2, 0.11f, S::leaf(), S::leaf()))}};
}

}  // namespace tc::test
