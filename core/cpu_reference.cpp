#include "core/cpu_reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <limits>

#include "core/rounded_cone.h"
#include "core/shading.h"

namespace tc {

FrameImages renderReferenceOpaque(const StyledLines& lines, const Camera& camera, const LightingSpec& light, int width,
                                  int height) {
    FrameImages img;
    img.allocate(width, height);
    const glm::vec3 forward = camera.forward();
    const glm::vec3 lightDir = lightDirectionWorld(light, camera);
    const bool ortho = camera.projection == Projection::Orthographic;
    const std::size_t segments = lines.segmentCount();

    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        for (int py = rows.begin(); py != rows.end(); ++py) {
            for (int px = 0; px < width; ++px) {
                Ray ray = pixelRay(camera, width, height, float(px), float(py));
                float best = std::numeric_limits<float>::infinity();
                std::size_t bestSeg = 0;
                glm::vec3 bestN(0.0f);
                for (std::size_t s = 0; s < segments; ++s) {
                    const glm::vec4& a = lines.positionRadius[lines.segmentVertices[2 * s]];
                    const glm::vec4& b = lines.positionRadius[lines.segmentVertices[2 * s + 1]];
                    const auto hit = firstSurfaceHit(ray, {glm::vec3(a), a.w, glm::vec3(b), b.w});
                    if (hit && hit->t < best) {
                        best = hit->t;
                        bestSeg = s;
                        bestN = hit->normal;
                    }
                }
                if (best == std::numeric_limits<float>::infinity()) continue;

                std::uint32_t v0 = lines.segmentVertices[2 * bestSeg], v1 = lines.segmentVertices[2 * bestSeg + 1];
                glm::vec3 x0(lines.positionRadius[v0]), x1(lines.positionRadius[v1]);
                glm::vec3 p = ray.origin + best * ray.dir;
                glm::vec3 ba = x1 - x0;
                float m0 = glm::dot(ba, ba);
                float s = m0 > 0.0f ? glm::clamp(glm::dot(p - x0, ba) / m0, 0.0f, 1.0f) : 0.0f;
                glm::vec3 base = glm::mix(glm::vec3(lines.color[v0]), glm::vec3(lines.color[v1]), s);
                glm::vec3 rgb = shadeBlinnPhong(base, bestN, ray.dir, lightDir, light);

                std::size_t i = std::size_t(py) * std::size_t(width) + std::size_t(px);
                img.depth[i] = ortho ? best : best * glm::dot(ray.dir, forward);
                img.normal[3 * i + 0] = bestN.x;
                img.normal[3 * i + 1] = bestN.y;
                img.normal[3 * i + 2] = bestN.z;
                img.id[i] = lines.polylineId[v0];
                img.rgba[4 * i + 0] = rgb.x;
                img.rgba[4 * i + 1] = rgb.y;
                img.rgba[4 * i + 2] = rgb.z;
                img.rgba[4 * i + 3] = 1.0f;
            }
        }
    });
    return img;
}

}  // namespace tc
