#include "gl/shader_library.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "gl/bindings.h"

namespace tc::gl {

ShaderLibrary& ShaderLibrary::instance() {
    static ShaderLibrary library;
    return library;
}

void ShaderLibrary::setOverrideDir(std::string dir) {
    if (!dir.empty() && !std::filesystem::is_directory(dir))
        throw InputError("--shader-dir: " + dir + ": not a directory");
    m_overrideDir = std::move(dir);
}

void ShaderLibrary::addEmbedded(const std::vector<EmbeddedShader>& shaders) {
    m_added.push_back(&shaders);
}

const EmbeddedShader* ShaderLibrary::findEmbedded(std::string_view name) const {
    for (const EmbeddedShader& shader : embeddedShaders())
        if (shader.name == name) return &shader;
    for (const std::vector<EmbeddedShader>* set : m_added)
        for (const EmbeddedShader& shader : *set)
            if (shader.name == name) return &shader;
    return nullptr;
}

namespace {

// The override file for `name`, or "" if there is none.
std::string overridePath(const std::string& dir, std::string_view name) {
    if (dir.empty()) return {};
    std::filesystem::path path = std::filesystem::path(dir) / std::string(name);
    return std::filesystem::is_regular_file(path) ? path.string() : std::string();
}

}  // namespace

std::string ShaderLibrary::source(std::string_view name) const {
    if (std::string path = overridePath(m_overrideDir, name); !path.empty()) {
        std::ifstream in(path, std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        if (!in) throw Error(ExitCode::Internal, "shader file " + path + ": cannot be read");
        return text.str();
    }
    if (const EmbeddedShader* shader = findEmbedded(name)) return std::string(shader->source);
    throw Error(ExitCode::Internal,
                "shader file '" + std::string(name) + "' is not embedded" +
                    (m_overrideDir.empty() ? std::string() : " and not in --shader-dir " + m_overrideDir) +
                    " (is it in shaders/ and was CMake re-run?)");
}

std::string ShaderLibrary::displayPath(std::string_view name) const {
    if (std::string path = overridePath(m_overrideDir, name); !path.empty()) return path;
    return "shaders/" + std::string(name);
}

namespace {

class Expander {
public:
    explicit Expander(ExpandedShader& out) : m_out(out) {}

    void emit(std::string_view line, int file, int lineNumber) {
        m_out.text.append(line);
        m_out.text.push_back('\n');
        m_out.origins.push_back({file, lineNumber});
    }

    void expand(const std::string& name) {
        // Include-once per stage: a second #include of a chunk is dropped, so chunks need no
        // guards and diamond includes (two chunks sharing a helper) just work.
        if (!m_included.insert(name).second) return;
        const ShaderLibrary& library = ShaderLibrary::instance();
        const std::string text = library.source(name);
        const int file = static_cast<int>(m_out.files.size());
        m_out.files.push_back(library.displayPath(name));

        static const std::regex include(R"re(^\s*#\s*include\s+"([^"]+)"\s*(//.*)?$)re");
        static const std::regex version(R"(^\s*#\s*version\b.*)");
        // In GLSL >= 3.30, as in C, `#line L N` numbers the *next* line L.
        auto lineMarker = [file](int nextLine) {
            return "#line " + std::to_string(file * kShaderLineStride + nextLine) + " " + std::to_string(file);
        };
        emit(lineMarker(1), -1, 0);
        std::istringstream lines(text);
        std::string line;
        for (int lineNumber = 1; std::getline(lines, line); ++lineNumber) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            std::smatch match;
            if (std::regex_match(line, match, include)) {
                expand(match[1].str());
                emit(lineMarker(lineNumber + 1), -1, 0);
            } else if (std::regex_match(line, version)) {
                throw Error(ExitCode::Internal, m_out.files[static_cast<size_t>(file)] + ":" +
                                                    std::to_string(lineNumber) +
                                                    ": #version is added by the shader library; remove it");
            } else {
                emit(line, file, lineNumber);
            }
        }
    }

private:
    ExpandedShader& m_out;
    std::set<std::string> m_included;
};

const char* stageName(GLenum stage) {
    switch (stage) {
        case GL_VERTEX_SHADER:
            return "vertex";
        case GL_TESS_CONTROL_SHADER:
            return "tessellation control";
        case GL_TESS_EVALUATION_SHADER:
            return "tessellation evaluation";
        case GL_GEOMETRY_SHADER:
            return "geometry";
        case GL_FRAGMENT_SHADER:
            return "fragment";
        case GL_COMPUTE_SHADER:
            return "compute";
        default:
            return "unknown";
    }
}

std::string joined(const std::vector<std::string>& items) {
    std::string s;
    for (const std::string& item : items) s += (s.empty() ? "" : ", ") + item;
    return s;
}

void printNumbered(const ExpandedShader& shader, const char* what) {
    std::fprintf(stderr, "--- %s shader %s ---\n", what, shader.files.at(1).c_str());
    std::istringstream lines(shader.text);
    std::string line;
    for (size_t i = 0; std::getline(lines, line); ++i) {
        const ExpandedShader::Origin origin = shader.origins.at(i);
        std::string where;
        if (origin.file >= 0)
            where = shader.files[static_cast<size_t>(origin.file)] + ":" + std::to_string(origin.line);
        std::fprintf(stderr, "%4zu %-40s| %s\n", i + 1, where.c_str(), line.c_str());
    }
}

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

std::string programLog(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

}  // namespace

ExpandedShader expandShader(std::string_view name, const std::vector<std::string>& defines) {
    ExpandedShader out;
    out.files.push_back("<preamble>");
    Expander expander(out);
    expander.emit("#version 450 core", 0, 1);
    static const std::regex define(R"(^([A-Za-z_][A-Za-z0-9_]*)(\s+(.*))?$)");
    for (const std::string& d : defines) {
        std::smatch match;
        if (!std::regex_match(d, match, define))
            throw Error(ExitCode::Internal,
                        "shader define '" + d + "' for " + std::string(name) + ": expected \"NAME\" or \"NAME VALUE\"");
        expander.emit("#define " + d, 0, static_cast<int>(out.origins.size()) + 1);
    }
    expander.expand(std::string(name));
    return out;
}

std::string rewriteShaderLog(std::string_view log, const std::vector<std::string>& files) {
    // Mesa "0:12(3): error", NVIDIA "0(12) : error", AMD/Intel "ERROR: 0:12: error".
    static const std::regex mesa(R"(^(\s*(?:ERROR: |WARNING: )?)(\d+):(\d+)\((\d+)\):)");
    static const std::regex nvidia(R"(^(\s*)(\d+)\((\d+)\)\s*:)");
    static const std::regex plain(R"(^(\s*(?:ERROR: |WARNING: )?)(\d+):(\d+):)");
    // "file:line" for source string `number` and reported line `line`.
    auto location = [&](const std::string& number, const std::string& line) -> std::string {
        size_t file = std::stoul(number);
        unsigned long lineNumber = std::stoul(line);
        if (lineNumber >= static_cast<unsigned long>(kShaderLineStride)) {
            file = lineNumber / kShaderLineStride;
            lineNumber %= kShaderLineStride;
        }
        if (file >= files.size()) return number + ":" + line;
        return files[file] + ":" + std::to_string(lineNumber);
    };

    std::string out;
    std::istringstream lines{std::string(log)};
    std::string line;
    while (std::getline(lines, line)) {
        std::smatch m;
        if (std::regex_search(line, m, mesa))
            line = m[1].str() + location(m[2], m[3]) + ":" + m[4].str() + ":" + m.suffix().str();
        else if (std::regex_search(line, m, nvidia))
            line = m[1].str() + location(m[2], m[3]) + ":" + m.suffix().str();
        else if (std::regex_search(line, m, plain))
            line = m[1].str() + location(m[2], m[3]) + ":" + m.suffix().str();
        out += line;
        out += '\n';
    }
    return out;
}

Program compileProgram(std::initializer_list<std::pair<GLenum, std::string_view>> stages,
                       const std::vector<std::string>& defines, bool verbose) {
    TC_CHECK(stages.size() > 0);
    const std::string defineList = defines.empty() ? "" : " (defines: " + joined(defines) + ")";
    std::vector<std::string> allDefines;
    for (const ShaderBinding& b : kShaderBindings)
        allDefines.push_back(std::string(b.define) + " " + std::to_string(b.point));
    allDefines.insert(allDefines.end(), defines.begin(), defines.end());
    std::vector<Shader> shaders;
    std::vector<std::string> stageFiles;
    for (const auto& [stage, name] : stages) {
        const ExpandedShader expanded = expandShader(name, allDefines);
        stageFiles.push_back(expanded.files.at(1));
        if (verbose) printNumbered(expanded, stageName(stage));

        Shader shader = Shader::create(stage);
        const char* text = expanded.text.c_str();
        const GLint length = static_cast<GLint>(expanded.text.size());
        glShaderSource(shader.id(), 1, &text, &length);
        glCompileShader(shader.id());
        GLint ok = GL_FALSE;
        glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
        const std::string log = rewriteShaderLog(shaderLog(shader.id()), expanded.files);
        if (!ok)
            throw Error(ExitCode::Internal, std::string("compiling ") + stageName(stage) + " shader " +
                                                expanded.files.at(1) + defineList + " failed:\n" + log);
        if (verbose && log.find_first_not_of(" \n") != std::string::npos) std::fprintf(stderr, "%s", log.c_str());
        shaders.push_back(std::move(shader));
    }

    Program program = Program::create();
    for (const Shader& shader : shaders) glAttachShader(program.id(), shader.id());
    glLinkProgram(program.id());
    // Detached shaders are deleted with their Shader owners; the program keeps its binary.
    for (const Shader& shader : shaders) glDetachShader(program.id(), shader.id());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok)
        throw Error(ExitCode::Internal,
                    "linking program " + joined(stageFiles) + defineList + " failed:\n" + programLog(program.id()));
    return program;
}

}  // namespace tc::gl
