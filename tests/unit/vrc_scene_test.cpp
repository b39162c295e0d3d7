// The render.vrc keys of the scene spec (core/scene.cpp, docs/scene-spec.md).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/scene.h"

namespace tc {
namespace {

using nlohmann::json;

std::string errorOf(const json& doc) {
    try {
        parseScene(doc, "scene.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no error>";
}

TEST(VrcScene, voxel_raycast_keys_parse_with_documented_defaults) {
    const Scene d = parseScene(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast"}})"),
                               "scene.json");
    EXPECT_EQ(d.render.technique, RenderTechnique::VoxelRaycast);
    EXPECT_EQ(d.render.vrc.resolution, 128);
    EXPECT_EQ(d.render.vrc.quantization, 32);
    EXPECT_FALSE(d.render.vrc.neighbors);
    EXPECT_FLOAT_EQ(d.render.vrc.opacityThreshold, 0.99f);
    EXPECT_FALSE(d.render.vrc.pathLengthOpacity);
    EXPECT_EQ(d.render.vrc.shadowMode, VrcSpec::ShadowMode::Soft);
    EXPECT_EQ(d.render.vrc.shadowLevel, 1);
    EXPECT_EQ(d.render.vrc.build, VrcSpec::Build::Auto);
    EXPECT_EQ(d.render.vrc.encoding, VrcSpec::Encoding::Compact16);
    EXPECT_FALSE(d.render.vrc.lod.enabled);
    EXPECT_FLOAT_EQ(d.render.vrc.lod.pixelFootprint, 1.0f);
    EXPECT_FLOAT_EQ(d.render.vrc.lod.opacityStart, 0.5f);

    const Scene s = parseScene(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "transparency": "kbuffer",
                   "vrc": {"resolution": 64, "quantization": 0, "neighbors": "on", "opacity_threshold": 0.5,
                           "path_length_opacity": true, "shadows": true, "shadow_aperture_deg": 20, "shadow_mode": "hard",
                           "shadow_level": 2, "build": "gpu", "encoding": "paper", "lod": {"enabled": true, "pixel_footprint": 4, "opacity_start": 0.25}}}})"),
                               "scene.json");
    EXPECT_EQ(s.render.vrc.resolution, 64);
    EXPECT_EQ(s.render.vrc.quantization, 0);
    EXPECT_TRUE(s.render.vrc.neighbors);
    EXPECT_FLOAT_EQ(s.render.vrc.opacityThreshold, 0.5f);
    EXPECT_TRUE(s.render.vrc.pathLengthOpacity);
    EXPECT_TRUE(s.render.vrc.shadows);
    EXPECT_FLOAT_EQ(s.render.vrc.shadowApertureDeg, 20.0f);
    EXPECT_EQ(s.render.vrc.shadowMode, VrcSpec::ShadowMode::Hard);
    EXPECT_EQ(s.render.vrc.shadowLevel, 2);
    EXPECT_EQ(s.render.vrc.build, VrcSpec::Build::Gpu);
    EXPECT_EQ(s.render.vrc.encoding, VrcSpec::Encoding::Paper);
    EXPECT_TRUE(s.render.vrc.lod.enabled);
    EXPECT_FLOAT_EQ(s.render.vrc.lod.pixelFootprint, 4.0f);
    EXPECT_FLOAT_EQ(s.render.vrc.lod.opacityStart, 0.25f);
}

TEST(VrcScene, bad_vrc_lod_keys_are_input_errors_naming_the_key) {
    auto error = [](const std::string& lod) {
        return errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
            "render": {"technique": "voxel_raycast", "vrc": {"lod": )" +
                                   lod + "}}}"));
    };
    const std::string enabled = error(R"({"enabled": "on"})");
    EXPECT_NE(enabled.find("render.vrc.lod.enabled"), std::string::npos) << enabled;
    const std::string footprint = error(R"({"pixel_footprint": -1})");
    EXPECT_NE(footprint.find("render.vrc.lod.pixel_footprint"), std::string::npos) << footprint;
    const std::string start = error(R"({"opacity_start": 1.5})");
    EXPECT_NE(start.find("render.vrc.lod.opacity_start"), std::string::npos) << start;
    const std::string typo = error(R"({"enable": true})");
    EXPECT_NE(typo.find("render.vrc.lod.enable"), std::string::npos) << typo;
    const std::string build = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"build": "gpgpu"}}})"));
    EXPECT_NE(build.find("render.vrc.build"), std::string::npos) << build;
    const std::string encoding = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"encoding": "packed"}}})"));
    EXPECT_NE(encoding.find("render.vrc.encoding"), std::string::npos) << encoding;
    const std::string notObject = error("true");
    EXPECT_NE(notObject.find("render.vrc.lod"), std::string::npos) << notObject;
}

TEST(VrcScene, bad_vrc_keys_are_input_errors_naming_the_key) {
    const std::string q = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"quantization": 91}}})"));
    EXPECT_NE(q.find("render.vrc.quantization"), std::string::npos) << q;
    const std::string typo = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"neighbours": "on"}}})"));
    EXPECT_NE(typo.find("render.vrc.neighbours"), std::string::npos) << typo;
    EXPECT_NE(typo.find("neighbors"), std::string::npos) << typo;  // did you mean
    const std::string n = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"neighbors": true}}})"));
    EXPECT_NE(n.find("render.vrc.neighbors"), std::string::npos) << n;
    const std::string mode = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"shadow_mode": "sharp"}}})"));
    EXPECT_NE(mode.find("render.vrc.shadow_mode"), std::string::npos) << mode;
    const std::string path = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"path_length_opacity": "on"}}})"));
    EXPECT_NE(path.find("render.vrc.path_length_opacity"), std::string::npos) << path;
}

TEST(VrcScene, paper_lighting_keys_parse_with_documented_defaults) {
    const Scene d = parseScene(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"ao": {}}}})"),
                               "scene.json");
    EXPECT_EQ(d.render.vrc.ao.method, VrcSpec::Ao::Method::ConeTraced);
    EXPECT_EQ(d.render.vrc.ao.rays, 16);
    EXPECT_EQ(d.render.vrc.ao.sphereRays, 100);
    EXPECT_FLOAT_EQ(d.render.vrc.ao.radiusVoxels, 15.0f);

    const Scene s = parseScene(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "ao": {"enabled": true},
                   "vrc": {"shadows": true, "shadow_mode": "density_cone",
                           "ao": {"method": "density_rays", "rays": 32, "sphere_rays": 50, "radius_voxels": 5}}}})"),
                               "scene.json");
    EXPECT_EQ(s.render.vrc.shadowMode, VrcSpec::ShadowMode::DensityCone);
    EXPECT_EQ(s.render.vrc.ao.method, VrcSpec::Ao::Method::DensityRays);
    EXPECT_EQ(s.render.vrc.ao.rays, 32);
    EXPECT_EQ(s.render.vrc.ao.sphereRays, 50);
    EXPECT_FLOAT_EQ(s.render.vrc.ao.radiusVoxels, 5.0f);
    auto mode = [](const char* m) {
        return parseScene(json::parse(std::string(R"({"dataset": {"generate": "tornado"}, "render": {"technique":
            "voxel_raycast", "vrc": {"shadow_mode": ")") +
                                      m + R"("}}})"),
                          "scene.json")
            .render.vrc.shadowMode;
    };
    EXPECT_EQ(mode("hard_tubes"), VrcSpec::ShadowMode::HardTubes);
    EXPECT_EQ(mode("hard"), VrcSpec::ShadowMode::Hard);
    EXPECT_EQ(mode("soft"), VrcSpec::ShadowMode::Soft);
    const Scene p = parseScene(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"ao": {"method": "precomputed"}}}})"),
                               "scene.json");
    EXPECT_EQ(p.render.vrc.ao.method, VrcSpec::Ao::Method::Precomputed);
}

TEST(VrcScene, bad_paper_lighting_keys_are_input_errors_naming_the_key) {
    const std::string method = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"ao": {"method": "ray_traced"}}}})"));
    EXPECT_NE(method.find("render.vrc.ao.method"), std::string::npos) << method;
    const std::string rays = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"ao": {"rays": 0}}}})"));
    EXPECT_NE(rays.find("render.vrc.ao.rays"), std::string::npos) << rays;
    const std::string sphere = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"ao": {"sphere_rays": 2000}}}})"));
    EXPECT_NE(sphere.find("render.vrc.ao.sphere_rays"), std::string::npos) << sphere;
    const std::string radius = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"ao": {"radius_voxels": 0.5}}}})"));
    EXPECT_NE(radius.find("render.vrc.ao.radius_voxels"), std::string::npos) << radius;
    const std::string typo = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"ao": {"ray": 8}}}})"));
    EXPECT_NE(typo.find("render.vrc.ao.ray"), std::string::npos) << typo;
    const std::string mode = errorOf(json::parse(R"({"dataset": {"generate": "tornado"},
        "render": {"technique": "voxel_raycast", "vrc": {"shadow_mode": "hard_tube"}}})"));
    EXPECT_NE(mode.find("render.vrc.shadow_mode"), std::string::npos) << mode;
}

}  // namespace
}  // namespace tc
