#include "core/transparent_reference.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/cap_clipping.h"
#include "core/rounded_cone.h"
#include "core/shading.h"

namespace tc {

FragmentView fragmentView(const Camera& camera, const Ray& ray) {
    const glm::vec3 forward = camera.forward();
    return {camera.eye, forward, camera.projection == Projection::Orthographic ? 1.0f : glm::dot(ray.dir, forward)};
}

bool segmentFragmentOf(const StyledLines& lines, std::size_t s, const Ray& ray, const FragmentView& view,
                       bool capClipping, const HaloGeometry* halo, SegmentFragment& out) {
    const std::uint32_t v0 = lines.segmentVertices[2 * s], v1 = lines.segmentVertices[2 * s + 1];
    const glm::vec4& a = lines.positionRadius[v0];
    const glm::vec4& b = lines.positionRadius[v1];
    const RoundedCone cone{glm::vec3(a), a.w, glm::vec3(b), b.w};
    const ConeInterval iv = intersectRoundedCone(ray, cone);
    if (!iv.hit && !halo) return false;
    // Planes only for segments the ray comes near: most pixels miss most segments.
    const ClipPlanes planes = capClipping ? segmentClipPlanes(lines, s) : ClipPlanes{};
    float t;
    glm::vec3 n;
    if (iv.hit && segmentFragment(ray, iv, planes, t, n)) {
        const glm::vec3 p = ray.origin + t * ray.dir;
        const glm::vec3 ba = cone.x1 - cone.x0;
        const float m0 = glm::dot(ba, ba);
        out = {t * view.depthScale,
               t,
               t,
               n,
               m0 > 0.0f ? glm::clamp(glm::dot(p - cone.x0, ba) / m0, 0.0f, 1.0f) : 0.0f,
               false};
        return true;
    }
    HaloHit h;
    if (!halo || !haloFragment(ray, cone, planes, view.eye, view.forward, *halo, h)) return false;
    out = {h.depth, h.depth / view.depthScale, h.tEntry, h.normal, h.along, true};
    return true;
}

void collectFragments(const StyledLines& lines, const Ray& ray, const Camera& camera, const LightingSpec& light,
                      bool capClipping, std::vector<TransparentFragment>& out, const LineHalo* halo) {
    out.clear();
    const FragmentView view = fragmentView(camera, ray);
    const glm::vec3 lightDir = lightDirectionWorld(light, camera);
    const HaloGeometry* ring = halo ? &halo->geometry : nullptr;
    const std::size_t segments = lines.segmentCount();
    for (std::size_t s = 0; s < segments; ++s) {
        SegmentFragment g;
        if (!segmentFragmentOf(lines, s, ray, view, capClipping, ring, g)) continue;
        const std::uint32_t v0 = lines.segmentVertices[2 * s], v1 = lines.segmentVertices[2 * s + 1];
        const glm::vec4 base = glm::mix(lines.color[v0], lines.color[v1], g.along);
        TransparentFragment f;
        f.depth = g.depth;
        f.t = g.t;
        f.segment = std::uint32_t(s);
        f.normal = g.normal;
        // Clamped like the GPU fragment (shaders/transparent_fragment.glsl): the k-buffer stores
        // RGBA8, so every transparent path blends colours in [0, 1]. The ring is not shaded.
        f.rgb = g.halo ? halo->color
                       : glm::clamp(shadeBlinnPhong(glm::vec3(base), g.normal, ray.dir, lightDir, light), 0.0f, 1.0f);
        f.alpha = base.w;
        f.halo = g.halo;
        out.push_back(f);
    }
    std::sort(out.begin(), out.end(), [](const TransparentFragment& l, const TransparentFragment& r) {
        return l.depth < r.depth || (l.depth == r.depth && l.segment < r.segment);
    });
}

FrameImages renderReferenceTransparent(const StyledLines& lines, const Camera& camera, const LightingSpec& light,
                                       int width, int height, bool capClipping, std::vector<int>* fragmentCount,
                                       const LineHalo* halo) {
    FrameImages img;
    img.allocate(width, height);
    if (fragmentCount) fragmentCount->assign(img.pixelCount(), 0);
    tbb::enumerable_thread_specific<std::vector<TransparentFragment>> scratch;

    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        std::vector<TransparentFragment>& frags = scratch.local();
        for (int py = rows.begin(); py != rows.end(); ++py) {
            for (int px = 0; px < width; ++px) {
                Ray ray = pixelRay(camera, width, height, float(px), float(py));
                collectFragments(lines, ray, camera, light, capClipping, frags, halo);
                std::size_t i = std::size_t(py) * std::size_t(width) + std::size_t(px);
                if (fragmentCount) (*fragmentCount)[i] = int(frags.size());
                if (frags.empty()) continue;

                glm::vec3 c(0.0f);
                float alpha = 0.0f;
                for (const TransparentFragment& f : frags) {
                    float w = (1.0f - alpha) * f.alpha;
                    c += w * f.rgb;
                    alpha += w;
                }
                const TransparentFragment& first = frags.front();
                img.depth[i] = first.depth;
                img.normal[3 * i + 0] = first.normal.x;
                img.normal[3 * i + 1] = first.normal.y;
                img.normal[3 * i + 2] = first.normal.z;
                img.id[i] = lines.polylineId[lines.segmentVertices[2 * first.segment]];
                img.rgba[4 * i + 0] = c.x;
                img.rgba[4 * i + 1] = c.y;
                img.rgba[4 * i + 2] = c.z;
                img.rgba[4 * i + 3] = alpha;
            }
        }
    });
    return img;
}

}  // namespace tc
