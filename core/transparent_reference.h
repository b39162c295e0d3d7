#pragma once
// CPU ground truth for transparent tubes: every rounded-cone fragment along every pixel ray,
// sorted and composited exactly. The GPU depth peeling is tested against it; it in turn is the
// reference for the k-buffer (Groß & Gumhold 2020, Sect. 4.2). Same ray (core/camera.h),
// intersection (core/rounded_cone.h), clipping (core/cap_clipping.h) and shading (core/shading.h)
// as the shaders.
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/frame_images.h"
#include "core/halo.h"
#include "core/scene.h"
#include "core/styled_lines.h"

namespace tc {

// One surface fragment of one segment on one ray.
struct TransparentFragment {
    float depth;            // view space: t * dot(dir, forward) (orthographic: t)
    float t;                // ray parameter, > 0
    std::uint32_t segment;  // index into segmentVertices / 2
    glm::vec3 normal;       // outward world normal of the tube
    glm::vec3 rgb;          // shaded, clamped to [0, 1], linear, not premultiplied
    float alpha;            // straight
    bool halo = false;      // a halo ring's fragment (core/halo.h), not the tube's
};

// The view a fragment's depth is measured in: eye, forward (camera.h) and, for this ray, the
// factor from the ray parameter to view depth (dot(dir, forward); orthographic: 1).
struct FragmentView {
    glm::vec3 eye, forward;
    float depthScale;
};
FragmentView fragmentView(const Camera& camera, const Ray& ray);

// Where segment `segment` meets `ray` as a transparent fragment, unshaded: the one fragment of
// core/cap_clipping.h's rule (planes of segmentClipPlanes when capClipping), or, with `halo` and
// no such fragment, its halo fragment (core/halo.h). `along` in [0, 1] is where on the segment the
// colour and alpha are interpolated: the hit's clamped projection onto the axis (the halo: the
// axis point nearest the ray). A halo fragment's t is its depth / depthScale, the ray parameter it
// sorts at; tSurface is where the ray meets the surface it belongs to (the tube's entry: t; the
// ring's entry), the point a region test takes.
struct SegmentFragment {
    float depth;
    float t;
    float tSurface;
    glm::vec3 normal;
    float along;
    bool halo;
};
bool segmentFragmentOf(const StyledLines& lines, std::size_t segment, const Ray& ray, const FragmentView& view,
                       bool capClipping, const HaloGeometry* halo, SegmentFragment& out);

// All fragments of `ray`, sorted by (depth, segment): per segment at most one, by
// segmentFragment (core/cap_clipping.h) with segmentClipPlanes when capClipping, else with no
// planes (tIn if > 0, else tOut if > 0: an eye inside a tube sees its inner wall). Colour and
// alpha are the vertex RGBA interpolated linearly by the hit's clamped projection parameter on
// the segment (as renderReferenceOpaque), colour shaded two-sided Blinn-Phong and clamped to
// [0, 1] (as the GPU transparent fragment: the k-buffer stores RGBA8). With `halo`, a segment the
// ray misses gives its halo fragment: halo.color (unshaded) with the interpolated alpha. `out` is
// cleared and reused (no allocation once it has grown).
void collectFragments(const StyledLines& lines, const Ray& ray, const Camera& camera, const LightingSpec& light,
                      bool capClipping, std::vector<TransparentFragment>& out, const LineHalo* halo = nullptr);

// Transparent rounded-cone tubes, row 0 = top. Per pixel-centre ray: collectFragments, then
// front-to-back "under" compositing with premultiplied colour, C += (1 - A) a c, A += (1 - A) a,
// in (depth, segment id) order, so equal depths (joint spheres without cap clipping) composite
// deterministically, like the GPU depth peeling. rgba: linear premultiplied (C, A). depth, normal
// and id: of the first (nearest) fragment, whatever its alpha; background as renderReferenceOpaque
// (+inf, 0, kBackgroundId, rgba 0). fragmentCount, when given, is resized to width x height and
// receives the number of fragments per pixel (depth complexity: a k-buffer with k >= its maximum
// holds every fragment). `halo`: as collectFragments. Parallel over rows (oneTBB);
// O(pixels x segments): small scenes only.
FrameImages renderReferenceTransparent(const StyledLines& lines, const Camera& camera, const LightingSpec& light,
                                       int width, int height, bool capClipping,
                                       std::vector<int>* fragmentCount = nullptr, const LineHalo* halo = nullptr);

}  // namespace tc
