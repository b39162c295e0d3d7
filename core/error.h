#pragma once
// Typed errors. Libraries throw these; only cli/ turns them into messages and exit codes.
#include <stdexcept>
#include <string>

namespace tc {

// Process exit codes, documented in README.md and `tubecast --help`.
enum class ExitCode : int {
    Ok = 0,
    Internal = 1,      // a bug: a check failed
    InvalidInput = 2,  // CLI usage, scene spec, dataset
    NoGpuContext = 3,  // no usable OpenGL backend
    CannotWrite = 4,   // output directory or file cannot be written
    FramesFailed = 5,  // --keep-going: some frames failed
    ImagesDiffer = 6,  // compare --fail: the PSNR is below the threshold
};

class Error : public std::runtime_error {
public:
    Error(ExitCode code, const std::string& message) : std::runtime_error(message), m_code(code) {}
    ExitCode code() const { return m_code; }

private:
    ExitCode m_code;
};

// Bad user input. The message already names where it comes from:
// "scene.json: render.kbuffer.k: expected integer 1..16, got 32".
class InputError : public Error {
public:
    explicit InputError(const std::string& message) : Error(ExitCode::InvalidInput, message) {}
};

// No headless OpenGL context could be made; says which backend failed and why.
class ContextError : public Error {
public:
    explicit ContextError(const std::string& message) : Error(ExitCode::NoGpuContext, message) {}
};

// An output could not be written (permissions, disk full, existing file without --overwrite).
class OutputError : public Error {
public:
    explicit OutputError(const std::string& message) : Error(ExitCode::CannotWrite, message) {}
};

}  // namespace tc

// Programmer-error checks that print both values (pbrt util/check.h style).
#define TC_CHECK(cond)                                                                                            \
    do {                                                                                                          \
        if (!(cond))                                                                                              \
            throw ::tc::Error(::tc::ExitCode::Internal,                                                           \
                              std::string(__FILE__) + ":" + std::to_string(__LINE__) + ": check failed: " #cond); \
    } while (false)

#define TC_CHECK_OP(a, op, b)                                                                                        \
    do {                                                                                                             \
        auto tc_va = (a);                                                                                            \
        auto tc_vb = (b);                                                                                            \
        if (!(tc_va op tc_vb))                                                                                       \
            throw ::tc::Error(::tc::ExitCode::Internal, std::string(__FILE__) + ":" + std::to_string(__LINE__) +     \
                                                            ": check failed: " #a " " #op " " #b " (" +              \
                                                            std::to_string(tc_va) + " vs " + std::to_string(tc_vb) + \
                                                            ")");                                                    \
    } while (false)
