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
    int device = -1;     // EGL: index into the enumerated EGL devices; -1 = automatic
    bool debug = false;  // KHR_debug synchronous callback, messages to the log (stderr)
    bool verbose = false;
};

struct ContextInfo {
    std::string backend;  // "egl-device", "egl-surfaceless", "osmesa"
    std::string device;   // which EGL device ran (index and DRM node / extension string), or ""
    std::string vendor, renderer, version, glslVersion;
    std::vector<std::string> extensions;  // the ones the pipeline cares about that are present
    bool hasExtension(const std::string& name) const;
};

// Owns the context; makes it current on creation. Move-only. Destroying it releases the
// context and the backend's display. Throws tc::ContextError saying which backend failed and why.
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

private:
    struct Impl;
    explicit Context(std::unique_ptr<Impl>);
    std::unique_ptr<Impl> m_impl;
};

Backend parseBackend(const std::string& name);  // throws InputError

}  // namespace tc::gl
