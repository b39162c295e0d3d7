#include "gl/context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/technique_registry.h"
#include "gl/gl_api.h"

// The few OSMesa functions and constants we use, declared here because <GL/osmesa.h> includes
// <GL/gl.h>, whose prototypes clash with the entry-point macros of gl/gl_api.h. Signatures and
// values are those of Mesa's include/GL/osmesa.h (stable ABI since Mesa 11).
extern "C" {
struct osmesa_context;
using OSMesaContext = osmesa_context*;
OSMesaContext OSMesaCreateContextAttribs(const int* attribList, OSMesaContext sharelist);
void OSMesaDestroyContext(OSMesaContext ctx);
GLboolean OSMesaMakeCurrent(OSMesaContext ctx, void* buffer, GLenum type, GLsizei width, GLsizei height);
using OSMESAproc = void (*)();
OSMESAproc OSMesaGetProcAddress(const char* funcName);
}

namespace tc::gl {
namespace {

constexpr int kOsMesaFormat = 0x22;        // OSMESA_FORMAT
constexpr int kOsMesaRgba = GL_RGBA;       // OSMESA_RGBA
constexpr int kOsMesaDepthBits = 0x30;     // OSMESA_DEPTH_BITS
constexpr int kOsMesaStencilBits = 0x31;   // OSMESA_STENCIL_BITS
constexpr int kOsMesaProfile = 0x33;       // OSMESA_PROFILE
constexpr int kOsMesaCoreProfile = 0x34;   // OSMESA_CORE_PROFILE
constexpr int kOsMesaMajorVersion = 0x36;  // OSMESA_CONTEXT_MAJOR_VERSION
constexpr int kOsMesaMinorVersion = 0x37;  // OSMESA_CONTEXT_MINOR_VERSION

constexpr int kMajor = 4, kMinor = 5;

// Extensions the render techniques choose variants by (interlock / ordering for k-buffers, 64-bit
// atomics for packed depth+id, ...). ContextInfo::extensions lists the present ones.
constexpr std::array kPipelineExtensions = {
    "GL_ARB_fragment_shader_interlock",
    "GL_NV_fragment_shader_interlock",
    "GL_INTEL_fragment_shader_ordering",
    "GL_ARB_shader_atomic_int64",
    "GL_NV_shader_atomic_int64",
    "GL_ARB_gpu_shader_int64",
    "GL_KHR_debug",
    "GL_ARB_bindless_texture",
    "GL_NV_gpu_shader5",
};

// Why one backend could not make a context: the reason, and what the user can do about it. Auto
// mode joins the reasons of both backends into one ContextError.
struct BackendFailure {
    std::string reason;
    std::string hint;
};

const char* eglErrorName(EGLint error) {
    switch (error) {
        case EGL_SUCCESS:
            return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED:
            return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS:
            return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC:
            return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE:
            return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG:
            return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT:
            return "EGL_BAD_CONTEXT";
        case EGL_BAD_CURRENT_SURFACE:
            return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY:
            return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH:
            return "EGL_BAD_MATCH";
        case EGL_BAD_NATIVE_PIXMAP:
            return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW:
            return "EGL_BAD_NATIVE_WINDOW";
        case EGL_BAD_PARAMETER:
            return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE:
            return "EGL_BAD_SURFACE";
        case EGL_CONTEXT_LOST:
            return "EGL_CONTEXT_LOST";
        default:
            return "unknown EGL error";
    }
}

std::string eglFailure(const char* call) {
    return std::string(call) + " failed: " + eglErrorName(eglGetError());
}

// Extension strings are space-separated; a substring test would match GL_ARB_foo in GL_ARB_foo2.
bool hasToken(const char* list, std::string_view token) {
    if (!list) return false;
    std::string_view rest(list);
    while (!rest.empty()) {
        const size_t space = rest.find(' ');
        if (rest.substr(0, space) == token) return true;
        if (space == std::string_view::npos) break;
        rest.remove_prefix(space + 1);
    }
    return false;
}

template <class Fn>
Fn eglProc(const char* name) {
    return reinterpret_cast<Fn>(eglGetProcAddress(name));
}

void* eglLoader(const char* name) {
    return reinterpret_cast<void*>(eglGetProcAddress(name));
}
void* osmesaLoader(const char* name) {
    return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
}

// EGL displays are per-process singletons: eglGetPlatformDisplay returns the same handle for the
// same platform and device, and eglTerminate on it destroys every context on it, including those
// of other Context objects (the shared test context). Count the users and terminate with the last.
std::map<EGLDisplay, int>& eglDisplayUsers() {
    static std::map<EGLDisplay, int> users;
    return users;
}

void debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei, const GLchar* message,
                   const void*) {
    auto typeName = [&] {
        switch (type) {
            case GL_DEBUG_TYPE_ERROR:
                return "error";
            case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
                return "deprecated";
            case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
                return "undefined behaviour";
            case GL_DEBUG_TYPE_PORTABILITY:
                return "portability";
            case GL_DEBUG_TYPE_PERFORMANCE:
                return "performance";
            case GL_DEBUG_TYPE_MARKER:
                return "marker";
            default:
                return "other";
        }
    };
    auto severityName = [&] {
        switch (severity) {
            case GL_DEBUG_SEVERITY_HIGH:
                return "high";
            case GL_DEBUG_SEVERITY_MEDIUM:
                return "medium";
            case GL_DEBUG_SEVERITY_LOW:
                return "low";
            default:
                return "notification";
        }
    };
    auto sourceName = [&] {
        switch (source) {
            case GL_DEBUG_SOURCE_API:
                return "api";
            case GL_DEBUG_SOURCE_SHADER_COMPILER:
                return "shader compiler";
            case GL_DEBUG_SOURCE_WINDOW_SYSTEM:
                return "window system";
            case GL_DEBUG_SOURCE_THIRD_PARTY:
                return "third party";
            case GL_DEBUG_SOURCE_APPLICATION:
                return "application";
            default:
                return "other";
        }
    };
    std::fprintf(stderr, "gl-debug: %s (%s, %s, id %u): %s\n", typeName(), severityName(), sourceName(), id, message);
}

}  // namespace

// What a Context owns. Named outside Context so the backend functions below can use it;
// Context::Impl is just this.
struct BackendContext {
    BackendContext() = default;
    BackendContext(const BackendContext&) = delete;
    BackendContext& operator=(const BackendContext&) = delete;

    Backend backend = Backend::Egl;  // Egl or OsMesa, never Auto
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext eglContext = EGL_NO_CONTEXT;
    OSMesaContext osmesaContext = nullptr;
    // OSMesaMakeCurrent needs a colour buffer even though we only render into FBOs.
    std::array<unsigned char, 4> osmesaBuffer{};
    ContextInfo info;

    ~BackendContext();
    void bind();
    void unbind();
};

struct Context::Impl : BackendContext {};

namespace {
// The context whose backend is bound and whose entry points gl_api.h points at. Tracked here
// rather than asked of the backends: Mesa's EGL and OSMesa share libglapi's "current context"
// slot, so OSMesaGetCurrentContext() returns a foreign pointer while an EGL context is current.
BackendContext* g_current = nullptr;
Backend g_loadedEntryPoints = Backend::Auto;  // Auto = none loaded yet
}  // namespace

void BackendContext::bind() {
    // Unbind another backend's context first: both backends write libglapi's current-context
    // slot, and glvnd skips an eglMakeCurrent of the context it believes is still current.
    if (g_current && g_current != this && g_current->backend != backend) g_current->unbind();
    if (backend == Backend::Egl) {
        if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, eglContext))
            throw ContextError(eglFailure("eglMakeCurrent"));
    } else if (!OSMesaMakeCurrent(osmesaContext, osmesaBuffer.data(), GL_UNSIGNED_BYTE, 1, 1)) {
        throw ContextError("OSMesaMakeCurrent failed");
    }
    g_current = this;
    if (g_loadedEntryPoints != backend) {
        // EGL (glvnd or Mesa) and OSMesa hand out context-independent entry points, so one load
        // per backend switch is enough.
        g_loadedEntryPoints = Backend::Auto;
        loadGlFunctions(backend == Backend::Egl ? eglLoader : osmesaLoader);
        g_loadedEntryPoints = backend;
    }
}

const ContextInfo& currentContextInfo() {
    TC_CHECK(g_current != nullptr);
    return g_current->info;
}

void BackendContext::unbind() {
    if (backend == Backend::Egl)
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    else
        OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);  // Mesa: null context and buffer = release
    if (g_current == this) g_current = nullptr;
}

BackendContext::~BackendContext() {
    if (g_current == this) unbind();
    if (eglContext != EGL_NO_CONTEXT) eglDestroyContext(display, eglContext);
    if (display != EGL_NO_DISPLAY) {
        auto& users = eglDisplayUsers();
        if (--users[display] <= 0) {
            users.erase(display);
            eglTerminate(display);
        }
    }
    if (osmesaContext) OSMesaDestroyContext(osmesaContext);
}

namespace {

struct EglDevice {
    EGLDeviceEXT handle;
    std::string drmNode;  // empty for devices without a DRM node (Mesa's software device)
    bool software;
    int cuda = -1;  // CUDA device ordinal (EGL_NV_device_cuda), -1 = not an NVIDIA device
};

// The EGL devices libEGL enumerates (EGL_EXT_device_enumeration / _base).
std::vector<EglDevice> eglDevices() {
    std::vector<EglDevice> devices;
    auto queryDevices = eglProc<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
    auto queryDeviceString = eglProc<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
    auto queryDeviceAttrib = eglProc<PFNEGLQUERYDEVICEATTRIBEXTPROC>("eglQueryDeviceAttribEXT");
    EGLint count = 0;
    if (!queryDevices || !queryDeviceString || !queryDevices(0, nullptr, &count) || count <= 0) return devices;
    std::vector<EGLDeviceEXT> handles(static_cast<size_t>(count));
    queryDevices(count, handles.data(), &count);
    handles.resize(static_cast<size_t>(std::max(count, 0)));
    for (EGLDeviceEXT handle : handles) {
        const char* extensions = queryDeviceString(handle, EGL_EXTENSIONS);
        const char* node =
            hasToken(extensions, "EGL_EXT_device_drm") ? queryDeviceString(handle, EGL_DRM_DEVICE_FILE_EXT) : nullptr;
        devices.push_back({handle, node ? node : "", hasToken(extensions, "EGL_MESA_device_software")});
        EGLAttrib cuda = -1;
        if (queryDeviceAttrib && hasToken(extensions, "EGL_NV_device_cuda") &&
            queryDeviceAttrib(handle, EGL_CUDA_DEVICE_NV, &cuda))
            devices.back().cuda = static_cast<int>(cuda);
    }
    return devices;
}

// "2 (/dev/dri/card1, CUDA device 0)": device i as messages and ContextInfo::device name it.
std::string describeDevice(const std::vector<EglDevice>& devices, size_t i) {
    const EglDevice& d = devices[i];
    return std::to_string(i) + " (" +
           (!d.drmNode.empty() ? d.drmNode
            : d.software       ? std::string("Mesa software device")
                               : std::string("no DRM node")) +
           (d.cuda >= 0 ? ", CUDA device " + std::to_string(d.cuda) : std::string()) + ")";
}

std::string deviceList(const std::vector<EglDevice>& devices) {
    std::string list;
    for (size_t i = 0; i < devices.size(); ++i) list += (i ? ", " : ": ") + describeDevice(devices, i);
    return list;
}

// The device to open: the job's CUDA device, config.device, or the first hardware device; -1 for
// none (Mesa's surfaceless platform then). Throws BackendFailure for a device that is not there.
int chooseEglDevice(const ContextConfig& config, const std::vector<EglDevice>& devices, bool hasDevices,
                    ContextInfo& info) {
    // The job's CUDA device (CUDA_VISIBLE_DEVICES / SLURM_JOB_GPUS): EGL enumerates every GPU of
    // the node whatever the job was given, so match the ordinal NVIDIA's driver reports. Devices
    // without EGL_NV_device_cuda (Mesa, other vendors) have nothing to match: fall through.
    const bool anyCuda = std::any_of(devices.begin(), devices.end(), [](const EglDevice& d) { return d.cuda >= 0; });
    if (config.cudaDevice >= 0 && anyCuda) {
        for (size_t i = 0; i < devices.size(); ++i)
            if (devices[i].cuda == config.cudaDevice) {
                info.cudaDevice = config.cudaDevice;
                return static_cast<int>(i);
            }
        throw BackendFailure{
            "CUDA device " + std::to_string(config.cudaDevice) + " has no EGL device" + deviceList(devices),
            "check CUDA_VISIBLE_DEVICES / SLURM_JOB_GPUS, or unset them and pick --device"};
    }
    if (config.device >= 0) {
        if (static_cast<size_t>(config.device) >= devices.size())
            throw BackendFailure{"EGL device " + std::to_string(config.device) + " does not exist; there are " +
                                     std::to_string(devices.size()) + " EGL devices" + deviceList(devices) +
                                     (hasDevices ? "" : " (libEGL lacks EGL_EXT_platform_device)"),
                                 "pick a device index below " + std::to_string(devices.size()) +
                                     ", or omit the device to choose automatically"};
        return config.device;
    }
    for (size_t i = 0; i < devices.size(); ++i)
        if (!devices[i].drmNode.empty() && !devices[i].software) return static_cast<int>(i);
    return -1;
}

// Opens and initialises the display of device `chosen` (-1: Mesa's surfaceless platform) into
// `impl`; returns the EGL version.
std::pair<EGLint, EGLint> openEglDisplay(const std::vector<EglDevice>& devices, int chosen,
                                         const char* clientExtensions, bool hasPlatformBase, BackendContext& impl) {
    auto getPlatformDisplay = eglProc<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
    if (chosen >= 0) {
        impl.display =
            getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[static_cast<size_t>(chosen)].handle, nullptr);
        impl.info.backend = "egl-device";
        impl.info.device = describeDevice(devices, static_cast<size_t>(chosen));
        if (impl.display == EGL_NO_DISPLAY)
            throw BackendFailure{
                "device " + impl.info.device + ": " + eglFailure("eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT)"),
                "try another --device or --backend osmesa"};
    } else {
        if (!hasPlatformBase || !getPlatformDisplay || !hasToken(clientExtensions, "EGL_MESA_platform_surfaceless")) {
            throw BackendFailure{
                "no hardware EGL device and libEGL offers no surfaceless platform "
                "(EGL_MESA_platform_surfaceless)",
                "install libegl-mesa0 and libgl1-mesa-dri (Mesa llvmpipe) or a GPU driver with EGL, "
                "or use --backend osmesa"};
        }
        impl.display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        impl.info.backend = "egl-surfaceless";
        if (impl.display == EGL_NO_DISPLAY)
            throw BackendFailure{eglFailure("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)"),
                                 "install libgl1-mesa-dri, or use --backend osmesa"};
    }

    EGLint eglMajor = 0, eglMinor = 0;
    if (!eglInitialize(impl.display, &eglMajor, &eglMinor)) {
        const std::string failure = eglFailure("eglInitialize");
        impl.display = EGL_NO_DISPLAY;  // nothing to terminate
        throw BackendFailure{impl.info.backend + ": " + failure,
                             "install libgl1-mesa-dri (Mesa's drivers), or use --backend osmesa"};
    }
    ++eglDisplayUsers()[impl.display];
    return {eglMajor, eglMinor};
}

// Creates the OpenGL 4.5 core context on the initialised display of `impl` (EGL eglMajor.eglMinor).
void createEglContext(const ContextConfig& config, EGLint eglMajor, EGLint eglMinor, BackendContext& impl) {
    const char* displayExtensions = eglQueryString(impl.display, EGL_EXTENSIONS);
    const bool egl15 = eglMajor > 1 || (eglMajor == 1 && eglMinor >= 5);
    if (!egl15 && !hasToken(displayExtensions, "EGL_KHR_create_context"))
        throw BackendFailure{"EGL " + std::to_string(eglMajor) + "." + std::to_string(eglMinor) +
                                 " without EGL_KHR_create_context cannot make a core profile context",
                             "update the GPU driver or Mesa, or use --backend osmesa"};
    if (!hasToken(displayExtensions, "EGL_KHR_surfaceless_context"))
        throw BackendFailure{"the EGL display lacks EGL_KHR_surfaceless_context",
                             "update the GPU driver or Mesa, or use --backend osmesa"};
    if (!eglBindAPI(EGL_OPENGL_API))
        throw BackendFailure{eglFailure("eglBindAPI(EGL_OPENGL_API)") + " (the EGL driver offers OpenGL ES only)",
                             "use --backend osmesa"};

    EGLConfig eglConfig = EGL_NO_CONFIG_KHR;
    if (!hasToken(displayExtensions, "EGL_KHR_no_config_context")) {
        // Any OpenGL-capable config will do: we never create a surface with it.
        const EGLint attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLint count = 0;
        if (!eglChooseConfig(impl.display, attribs, &eglConfig, 1, &count) || count < 1)
            throw BackendFailure{"no EGL config supports desktop OpenGL (" + eglFailure("eglChooseConfig") + ")",
                                 "use --backend osmesa"};
    }

    // The EGL_KHR_create_context names have the same values as EGL 1.5's, so one list serves both.
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION_KHR,
                                     kMajor,
                                     EGL_CONTEXT_MINOR_VERSION_KHR,
                                     kMinor,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR,
                                     EGL_CONTEXT_FLAGS_KHR,
                                     config.debug ? EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR : 0,
                                     EGL_NONE};
    impl.eglContext = eglCreateContext(impl.display, eglConfig, EGL_NO_CONTEXT, contextAttribs);
    if (impl.eglContext == EGL_NO_CONTEXT) {
        const EGLint error = eglGetError();
        throw BackendFailure{std::string("eglCreateContext(OpenGL 4.5 core) failed: ") + eglErrorName(error) +
                                 (error == EGL_BAD_MATCH ? " (the driver has no OpenGL 4.5 core profile)" : ""),
                             "update the GPU driver or Mesa (>= 20), or use --backend osmesa"};
    }
}

// Makes an EGL context for config.device (or the first hardware device, else Mesa's surfaceless
// platform) and leaves `impl` owning what it created, so a throw cleans up through ~BackendContext.
void createEgl(const ContextConfig& config, BackendContext& impl) {
    impl.backend = Backend::Egl;
    // Null when libEGL lacks EGL_EXT_client_extensions (or has no vendor at all); treat as empty.
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const bool hasPlatformBase = hasToken(clientExtensions, "EGL_EXT_platform_base");
    const bool hasDevices =
        hasPlatformBase && hasToken(clientExtensions, "EGL_EXT_platform_device") &&
        (hasToken(clientExtensions, "EGL_EXT_device_enumeration") || hasToken(clientExtensions, "EGL_EXT_device_base"));
    const std::vector<EglDevice> devices = hasDevices ? eglDevices() : std::vector<EglDevice>{};
    const int chosen = chooseEglDevice(config, devices, hasDevices, impl.info);
    const auto [eglMajor, eglMinor] = openEglDisplay(devices, chosen, clientExtensions, hasPlatformBase, impl);
    createEglContext(config, eglMajor, eglMinor, impl);
}

void createOsMesa(const ContextConfig&, BackendContext& impl) {
    impl.backend = Backend::OsMesa;
    impl.info.backend = "osmesa";
    // No depth or stencil: the dummy buffer is never drawn to; render targets are FBOs.
    const int attribs[] = {kOsMesaFormat,
                           kOsMesaRgba,
                           kOsMesaDepthBits,
                           0,
                           kOsMesaStencilBits,
                           0,
                           kOsMesaProfile,
                           kOsMesaCoreProfile,
                           kOsMesaMajorVersion,
                           kMajor,
                           kOsMesaMinorVersion,
                           kMinor,
                           0};
    impl.osmesaContext = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!impl.osmesaContext)
        throw BackendFailure{
            "OSMesaCreateContextAttribs could not make an OpenGL 4.5 core context "
            "(OSMesa gives no reason; it needs Mesa >= 20 with llvmpipe)",
            "install libosmesa6 and libgl1-mesa-dri, or use --backend egl"};
}

// Reads what the context is; throws BackendFailure when it is older than 4.5.
void queryInfo(ContextInfo& info) {
    auto str = [](GLenum name) {
        const GLubyte* s = glGetString(name);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    info.vendor = str(GL_VENDOR);
    info.renderer = str(GL_RENDERER);
    info.version = str(GL_VERSION);
    info.glslVersion = str(GL_SHADING_LANGUAGE_VERSION);

    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < kMajor * 10 + kMinor)
        throw BackendFailure{"the context is OpenGL " + std::to_string(major) + "." + std::to_string(minor) + " (" +
                                 info.renderer + "), tubecast needs 4.5 core",
                             "update the GPU driver or Mesa (llvmpipe has 4.5 since Mesa 20)"};

    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    info.allExtensions.clear();
    for (GLint i = 0; i < count; ++i) {
        const GLubyte* s = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
        if (s) info.allExtensions.emplace_back(reinterpret_cast<const char*>(s));
    }
    std::sort(info.allExtensions.begin(), info.allExtensions.end());
    info.extensions.clear();
    for (const char* name : kPipelineExtensions)
        if (info.hasExtension(name)) info.extensions.emplace_back(name);
}

void enableDebugOutput() {
    glEnable(GL_DEBUG_OUTPUT);
    // Synchronous: the message prints inside the offending call, so a debugger breakpoint in
    // debugCallback shows the caller.
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, nullptr);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
    // Compile errors reach the user through the shader library, which maps them to file names;
    // the raw copies here would only repeat them with source-string numbers.
    glDebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_FALSE);
}

// Fills `impl`, an empty BackendContext; on a throw, its destructor releases what was made.
void createBackend(Backend backend, const ContextConfig& config, BackendContext& impl) {
    if (backend == Backend::Egl)
        createEgl(config, impl);
    else
        createOsMesa(config, impl);
    try {
        impl.bind();
    } catch (const ContextError& e) {
        throw BackendFailure{e.what(), backend == Backend::Egl ? "use --backend osmesa" : "use --backend egl"};
    }
    queryInfo(impl.info);
    if (config.debug) enableDebugOutput();
}

const char* backendName(Backend backend) {
    return backend == Backend::Egl ? "EGL" : "OSMesa";
}

}  // namespace

bool ContextInfo::hasExtension(const std::string& name) const {
    return std::binary_search(allExtensions.begin(), allExtensions.end(), name);
}

Context Context::create(const ContextConfig& config) {
    const char* forceNoGl = std::getenv("TUBECAST_FORCE_NO_GL");
    if (forceNoGl && std::string_view(forceNoGl) == "1")
        throw ContextError(
            "no OpenGL backend available: TUBECAST_FORCE_NO_GL=1 is set (test hook); "
            "unset it");

    if (config.device >= 0 && config.backend == Backend::OsMesa)
        throw InputError("--device " + std::to_string(config.device) +
                         ": only the EGL backend has devices, got --backend osmesa");
    // An explicit device asks for EGL: falling back to OSMesa would hide a wrong index.
    const Backend requested = config.device >= 0 && config.backend == Backend::Auto ? Backend::Egl : config.backend;

    std::unique_ptr<Impl> impl;
    if (requested == Backend::Auto) {
        std::string failures;
        for (Backend backend : {Backend::Egl, Backend::OsMesa}) {
            try {
                auto candidate = std::make_unique<Impl>();
                createBackend(backend, config, *candidate);
                impl = std::move(candidate);
                break;
            } catch (const BackendFailure& f) {
                failures += std::string(failures.empty() ? "" : "; ") + backendName(backend) + " failed: " + f.reason;
            }
        }
        if (!impl)
            throw ContextError("no OpenGL 4.5 context could be created: " + failures +
                               ". Install libgl1-mesa-dri and libosmesa6 (Mesa llvmpipe) or a GPU "
                               "driver with EGL");
    } else {
        try {
            impl = std::make_unique<Impl>();
            createBackend(requested, config, *impl);
        } catch (const BackendFailure& f) {
            throw ContextError(std::string(backendName(requested)) + " backend failed: " + f.reason + "; " + f.hint);
        }
    }

    if (config.verbose) {
        const ContextInfo& i = impl->info;
        std::fprintf(stderr, "tubecast: OpenGL context: %s%s%s, %s, %s, GLSL %s\n", i.backend.c_str(),
                     i.device.empty() ? "" : " device ", i.device.c_str(), i.renderer.c_str(), i.version.c_str(),
                     i.glslVersion.c_str());
    }
    return Context(std::move(impl));
}

Context::Context(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;
Context::~Context() = default;

const ContextInfo& Context::info() const {
    TC_CHECK(m_impl);
    return m_impl->info;
}

bool Context::isSoftwareRenderer() const {
    return isSoftwareRasterizer(info().renderer);
}

void Context::makeCurrent() {
    TC_CHECK(m_impl);
    m_impl->bind();
}

Backend parseBackend(const std::string& name) {
    if (name == "auto") return Backend::Auto;
    if (name == "egl") return Backend::Egl;
    if (name == "osmesa") return Backend::OsMesa;
    throw InputError("--backend: expected one of auto, egl, osmesa, got '" + name + "'");
}

}  // namespace tc::gl
