#pragma once
// The shader files of shaders/, compiled into the binary by shaders/embed_shaders.cmake.
#include <string_view>
#include <vector>

namespace tc::gl {

struct EmbeddedShader {
    std::string_view name;  // file name, e.g. "rounded_cone.frag"
    std::string_view source;
};

const std::vector<EmbeddedShader>& embeddedShaders();

}  // namespace tc::gl
