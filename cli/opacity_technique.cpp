#include "cli/opacity_technique.h"

#include "core/error.h"
#include "gl/opacity_renderer.h"
#include "io/opacity_system_dump.h"

namespace tc::cli {

std::unique_ptr<gl::Technique> makeOpacityTechnique(const Scene& scene, const StyledLines& styled,
                                                    const LineSet& data) {
    const OpacityOptimizationSpec& spec = scene.render.opacity;
    const std::vector<float>* attribute = nullptr;
    if (spec.importance == OpacityOptimizationSpec::Importance::Attribute) {
        const Attribute* a = data.attribute(spec.attribute);
        if (!a) {
            std::string names;
            for (const Attribute& x : data.attributes) names += (names.empty() ? "" : ", ") + x.name;
            throw InputError(scene.file + ": render.opacity.importance.attribute: the dataset has no attribute \"" +
                             spec.attribute + "\" (it has: " + (names.empty() ? "none" : names) + ")");
        }
        attribute = &a->values;
    }
    gl::OpacityRenderer::SystemSink sink;
    if (!spec.dumpDir.empty()) {
        const std::string dir = spec.dumpDir;
        sink = [dir](const gl::OpacitySystem& s) {
            const SparseMatrixD q = s.energy->assemble();
            const Eigen::VectorXd c = s.energy->linearTerm();
            const Eigen::VectorXd lower = Eigen::VectorXd::Zero(c.size()), upper = Eigen::VectorXd::Ones(c.size());
            writeOpacitySystem(dir, s.frame, {&q, &c, s.importance, &lower, &upper, s.solution, s.displayed, s.solve});
        };
    }
    Scene rasterized = scene;
    rasterized.render.technique = RenderTechnique::Rasterized;
    return gl::OpacityRenderer::create(rasterized, styled, attribute, std::move(sink));
}

}  // namespace tc::cli
