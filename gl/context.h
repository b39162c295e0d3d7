#pragma once
// A headless OpenGL 4.5 core context: EGL (device platform or Mesa surfaceless) or OSMesa.
// Rendering goes to framebuffer objects only; there is no default framebuffer to draw to.
#include <memory>
#include <string>
#include <vector>

namespace tc::gl {

enum class Backend { Auto, Egl, OsMesa };

struct ContextConfig {
    Backend backend = Backend::Auto;
    int device = -1;      // EGL: index into the enumerated EGL devices; -1 = automatic.
                          // Implies EGL with Backend::Auto; InputError with Backend::OsMesa.
    int cudaDevice = -1;  // EGL: pick the device whose EGL_CUDA_DEVICE_NV is this ordinal; ignored
                          // (device / automatic choice applies) when no device has
                          // EGL_NV_device_cuda, as on Mesa. -1 = no CUDA matching.
    bool debug = false;   // KHR_debug synchronous callback, messages to the log (stderr)
    bool verbose = false;
};

struct ContextInfo {
    std::string backend;  // "egl-device", "egl-surfaceless", "osmesa"
    std::string device;   // which EGL device ran (index and DRM node / extension string), or ""
    int cudaDevice = -1;  // the CUDA ordinal matched through EGL_NV_device_cuda, or -1
    std::string vendor, renderer, version, glslVersion;
    std::vector<std::string> extensions;               // the ones the pipeline cares about that are present
    std::vector<std::string> allExtensions;            // every GL_EXTENSIONS entry, sorted
    bool hasExtension(const std::string& name) const;  // searches allExtensions
};

// Owns the context; makes it current on the calling thread on creation and loads the GL entry
// points of its backend (gl/gl_api.h). Move-only. Destroying it unbinds it if current and
// releases the context and, with the last context on it, the backend's EGL display.
// Throws tc::ContextError saying which backend failed, why, and what to try.
//
// One context is current at a time per process: the GL entry points are process-wide. A context
// has no default framebuffer worth drawing to (EGL: none; OSMesa: a 1x1 dummy) and its initial
// viewport is unspecified, so renderers set glViewport for each framebuffer they bind.
//
// Test hook: with the environment variable TUBECAST_FORCE_NO_GL=1, create() behaves as if no
// backend were available and throws ContextError (the CLI tests check exit code 3 with it).
class Context {
public:
    static Context create(const ContextConfig& config);
    Context(Context&&) noexcept;
    Context& operator=(Context&&) noexcept;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    ~Context();

    const ContextInfo& info() const;
    bool isSoftwareRenderer() const;  // llvmpipe, softpipe, swrast

    // Makes this context current again and, if another backend's context was current, unbinds
    // that one and reloads the GL entry points. Only needed by processes that juggle several
    // contexts (the GL tests); a renderer has one context, current since create().
    void makeCurrent();

private:
    struct Impl;
    explicit Context(std::unique_ptr<Impl>);
    std::unique_ptr<Impl> m_impl;
};

Backend parseBackend(const std::string& name);  // throws InputError

// The info of the Context that is current on this thread (techniques choose code paths by the
// extensions it lists). Checks that one is current.
const ContextInfo& currentContextInfo();

}  // namespace tc::gl
