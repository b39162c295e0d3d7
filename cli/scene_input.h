#pragma once
// What `render`, `validate` and `scene` take where a scene is expected: a scene file (.json), or a
// dataset file alone, which means its default scene (core/default_scene.h). The dataset is read
// once: the default scene depends on it, and the render reuses it.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/scene.h"
#include "io/dataset.h"

namespace tc::cli {

struct SceneInput {
    Scene scene;
    std::optional<DatasetLoad> data;  // a dataset given alone: already read
};

// The default scene of the dataset at `path` (read into `load`), as JSON.
nlohmann::json defaultSceneJson(const std::string& path, DatasetLoad& load);

// A scene file, or a dataset's default scene with `overrides` applied (messages name the dataset
// file). Throws InputError as loadScene and loadDataset.
SceneInput loadSceneInput(const std::string& path, const std::vector<std::string>& overrides);

}  // namespace tc::cli
