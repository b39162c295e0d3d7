#include "cli/frame_overlay.h"

#include "core/particle_styling.h"
#include "core/styling.h"
#include "io/dataset.h"
#include "io/frame_overlay.h"

namespace tc::cli {

FrameOverlay makeFrameOverlay(const Scene& scene, const DatasetLoad& data,
                              const std::function<void(const std::string&)>& note) {
    const OverlaySpec& spec = scene.overlay;
    if (!spec.any()) return nullptr;
    const ColorSpec& color = scene.style.color;
    const bool particles = data.isParticles();
    const bool mapped = !color.attribute.empty() && !color.direction;
    const Colormap* colormap = mapped ? &styleColormap(color, scene.file) : nullptr;
    std::optional<ValueRange> lineRange;
    if (mapped && !particles && data.lines.polylineCount() > 0)
        lineRange = colorMappingRange(data.lines, scene.style, scene.file);
    if (spec.legend && !mapped && !(color.direction && spec.legend->directionKey))
        note(color.direction ? "overlay.legend: style.color is \"direction\" and direction_key is false: no legend"
                             : "overlay.legend: style.color is not an attribute mapping: no colour bar");

    return [&scene, &data, colormap, lineRange, particles](FrameImages& frame, int frameNumber, const Camera& camera) {
        const OverlaySpec& spec = scene.overlay;
        OverlayContent content;
        content.spec = &spec;
        content.background = scene.image.background;
        content.directionColors = scene.style.color.direction;
        content.title = scene.style.color.attribute;
        content.camera = camera;
        content.labels = {frameNumber, double(frameNumber) / double(spec.fps), scene.style.color.attribute,
                          scene.render.technique.name()};
        std::optional<ValueRange> range = lineRange;
        if (particles && !data.particles.frames.empty()) {
            const ParticleSet& shown =
                data.particles.frames[data.particles.dataFrameFor(frameNumber, scene.dataset.frame)];
            if (shown.time) content.labels.time = *shown.time;
            if (colormap && spec.legend) range = colorMappingRange(shown, scene.style, scene.file);
        }
        if (colormap && range) {
            content.colormap = colormap;
            content.range = *range;
        }
        drawOverlay(frame, content);
    };
}

}  // namespace tc::cli
