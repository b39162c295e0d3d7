#pragma once
// GLSL sources by file name and the one way tubecast compiles them.
//
// Shader files live in shaders/ and are embedded at build time (gl/embedded_shaders.h), so an
// installed binary needs no source tree; --shader-dir makes files in another directory win, for
// iterating on a shader without rebuilding. A stage is assembled as
//     #version 450 core
//     #define NAME VALUE          (one per define, in order)
//     <the file, with #include "other.glsl" lines expanded>
// Variants are chosen by defines, never by editing the text. GLSL's #line takes a source-string
// *number*, not a name, so each stage numbers its files (0 = the preamble above, 1.. = files in
// order of first inclusion) and compile logs are rewritten to name the real file and line:
//     1:100012(3): error: ...   ->   shaders/rounded_cone.frag:12:3: error: ...
// The #line markers also encode the file in the line number (kShaderLineStride * file + line):
// Mesa 22 reports source-string number 0 for many errors (bison's default location merge drops
// the number), so the line alone must say which file it is in.
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gl/embedded_shaders.h"
#include "gl/objects.h"

namespace tc::gl {

class ShaderLibrary {
public:
    // The process-wide library. Configure it (setOverrideDir) before compiling; not thread-safe.
    static ShaderLibrary& instance();

    // Files found in `dir` are used instead of the embedded copies; "" turns the override off.
    // Throws tc::InputError if `dir` is not a directory ("--shader-dir: ...").
    void setOverrideDir(std::string dir);
    const std::string& overrideDir() const { return m_overrideDir; }

    // Adds embedded files looked up after the binary's own: a test binary's shaders
    // (tests/gl/test_shaders.h). `shaders` must outlive the library; their names must not repeat
    // the binary's.
    void addEmbedded(const std::vector<EmbeddedShader>& shaders);

    // The text of shader file `name` ("rounded_cone.frag"). Throws tc::Error(ExitCode::Internal)
    // if neither the override directory nor an embedded set has it.
    std::string source(std::string_view name) const;
    // Where `name` is read from, as messages should name it: "<dir>/name", or "shaders/name" for
    // an embedded file (the shaders/ directory of the binary's or the test's sources).
    std::string displayPath(std::string_view name) const;

private:
    ShaderLibrary() = default;
    const EmbeddedShader* findEmbedded(std::string_view name) const;

    std::string m_overrideDir;
    std::vector<const std::vector<EmbeddedShader>*> m_added;
};

// #line numbers of file N (N >= 1) start at N * kShaderLineStride; files have fewer lines.
inline constexpr int kShaderLineStride = 100000;

// One stage's assembled source and what it was assembled from. Exposed for tests and tools.
struct ExpandedShader {
    std::string text;                // what glShaderSource receives
    std::vector<std::string> files;  // source-string number -> display path; [0] = "<preamble>"
    struct Origin {
        int file = -1;  // -1: a #line marker we inserted
        int line = 0;
    };
    std::vector<Origin> origins;  // one per line of `text`
};

// Assembles the stage from file `name` of the library (see the top of this header). Each file is
// included at most once per stage, so chunks need no include guards. Throws tc::Error(Internal)
// for a malformed define, a missing file or a #version line in a file.
ExpandedShader expandShader(std::string_view name, const std::vector<std::string>& defines);

// Rewrites "N:L(C):", "N(L) :" and "N:L:" locations (Mesa, NVIDIA, AMD/Intel) in a compile log
// to "file:line:C:" / "file:line:" using `files` (ExpandedShader::files) and the line encoding
// above; a line below kShaderLineStride is in source string N. Other text passes unchanged.
std::string rewriteShaderLog(std::string_view log, const std::vector<std::string>& files);

// Compiles and links a program from (stage, file name) pairs, e.g.
//     compileProgram({{GL_VERTEX_SHADER, "lines.vert"}, {GL_FRAGMENT_SHADER, "lines.frag"}},
//                    {"KBUFFER_K 8", "USE_INTERLOCK"});
// Each define is "NAME" or "NAME VALUE"; every stage gets the binding points of gl/bindings.h
// (kShaderBindings) as defines before them. Needs a current context. Throws tc::Error(Internal) with
// the rewritten log on a compile or link failure. With `verbose`, prints each stage's numbered
// source (and any compiler warnings) to stderr.
Program compileProgram(std::initializer_list<std::pair<GLenum, std::string_view>> stages,
                       const std::vector<std::string>& defines = {}, bool verbose = false);

}  // namespace tc::gl
