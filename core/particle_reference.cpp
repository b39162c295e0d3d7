#include "core/particle_reference.h"

#include <algorithm>
#include <cmath>

#include "core/shading.h"
#include "core/sphere_glyph.h"

namespace tc {

FrameImages renderParticlesReference(const StyledParticles& particles, const Camera& camera, int width, int height,
                                     const ParticleReferenceOptions& options) {
    FrameImages img;
    img.allocate(width, height);
    const float aspect = float(width) / float(height);
    const glm::vec3 lightDir = lightDirectionWorld(options.lighting, camera);
    const SpheresSpec& sp = options.spheres;
    const float P = densityNormalisation(sp.density, sp.innerRadius);

    // Screen rectangles first, so a pixel only tests the spheres that can cover it.
    struct Candidate {
        std::size_t index;
        glm::vec4 rect;
    };
    std::vector<Candidate> candidates;
    for (std::size_t i = 0; i < particles.size(); ++i) {
        glm::vec4 rect;
        const glm::vec4& cr = particles.centerRadius[i];
        if (projectedSphereBounds(camera, aspect, glm::vec3(cr), cr.w, 0.0f, rect)) candidates.push_back({i, rect});
    }

    struct Hit {
        float tNear;
        std::size_t index;
        SphereInterval interval;
    };
    std::vector<Hit> hits;
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px) {
            const Ray ray = pixelRay(camera, width, height, float(px), float(py));
            const float sx = 2.0f * (float(px) + 0.5f) / float(width) - 1.0f;
            const float sy = 1.0f - 2.0f * (float(py) + 0.5f) / float(height);
            // A pixel on the rectangle's edge may still be hit (rounding): a small margin; the
            // intersection decides.
            const float m = 4.0f / float(std::min(width, height));
            hits.clear();
            for (const Candidate& c : candidates) {
                if (sx < c.rect.x - m || sx > c.rect.z + m || sy < c.rect.y - m || sy > c.rect.w + m) continue;
                const glm::vec4& cr = particles.centerRadius[c.index];
                SphereInterval s = intersectSphere(ray, glm::vec3(cr), cr.w);
                if (s.hit) hits.push_back({s.tNear, c.index, s});
            }
            std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
                return a.tNear != b.tNear ? a.tNear < b.tNear : a.index < b.index;
            });
            const std::size_t pix = std::size_t(py) * std::size_t(width) + std::size_t(px);
            glm::vec4 acc(0.0f);
            for (std::size_t k = 0; k < hits.size(); ++k) {
                const Hit& h = hits[k];
                const glm::vec4& cr = particles.centerRadius[h.index];
                const glm::vec4& col = particles.color[h.index];
                const glm::vec3 p = ray.origin + h.tNear * ray.dir;
                const glm::vec3 n = (p - glm::vec3(cr)) / cr.w;
                float alpha = 1.0f;
                glm::vec3 e;
                if (options.opaque) {
                    e = sphereEmission(glm::vec3(col), n, ray.dir, lightDir, options.lighting, 0.0f, 0.0f, 1.0f,
                                       glm::vec3(0.0f));
                } else {
                    alpha = sphereOpacity(col.w, unitOpticalDepth(sp.density, sp.innerRadius, h.interval, cr.w), P);
                    e = sphereEmission(glm::vec3(col), n, ray.dir, lightDir, options.lighting, sp.alphaRv, sp.alphaA,
                                       1.0f, glm::vec3(0.0f));
                }
                if (k == 0) {
                    const float depth = camera.projection == Projection::Orthographic
                                            ? h.tNear
                                            : h.tNear * glm::dot(ray.dir, camera.forward());
                    img.depth[pix] = depth;
                    img.normal[3 * pix + 0] = n.x;
                    img.normal[3 * pix + 1] = n.y;
                    img.normal[3 * pix + 2] = n.z;
                    img.id[pix] = particles.id[h.index];
                }
                // "Under": the GPU's glBlendFunc(ONE_MINUS_DST_ALPHA, ONE) on premultiplied colour.
                const float w = 1.0f - acc.w;
                acc += glm::vec4(w * (alpha * e), w * alpha);
                if (options.opaque) break;
            }
            for (int c = 0; c < 4; ++c) img.rgba[4 * pix + std::size_t(c)] = acc[c];
        }
    return img;
}

}  // namespace tc
