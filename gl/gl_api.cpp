#include "gl/gl_api.h"

#include <cstring>
#include <string>

#include "core/error.h"

// Definitions of the pointers declared in gl_functions_generated.h. The macro argument `name`
// expands to the qualified ::tc::gl::fn::name, which is a valid out-of-namespace definition.
#define TC_GL_FUNCTION(Pfn, name, version) Pfn name = nullptr;
#include "gl/gl_function_table.inl"
#undef TC_GL_FUNCTION

namespace tc::gl {
namespace {

struct Entry {
    const char* name;
    int version;   // major * 10 + minor
    void* target;  // address of the function pointer variable
};

// `#name` stringifies the unexpanded argument ("glClear"); `&name` takes the pointer's address.
#define TC_GL_FUNCTION(Pfn, name, version) {#name, version, &name},
const Entry kEntries[] = {
#include "gl/gl_function_table.inl"
};
#undef TC_GL_FUNCTION

// The version every tubecast context is created with; older entry points must all resolve.
constexpr int kRequiredVersion = 45;

}  // namespace

void loadGlFunctions(ProcLoader loader) {
    std::string missing;
    int missingCount = 0;
    for (const Entry& e : kEntries) {
        void* proc = loader(e.name);
        // A function promoted to core from ARB_robustness/KHR_robustness may be known to the
        // backend only by its extension name: OSMesa (Mesa 22) resolves glGetnTexImageARB but
        // not glGetnTexImage. Same signature and semantics, so the suffixed entry point serves.
        for (const char* suffix : {"ARB", "KHR"}) {
            if (proc) break;
            proc = loader((std::string(e.name) + suffix).c_str());
        }
        // POSIX guarantees data and function pointers have the same representation; memcpy keeps
        // the conversion from void* well-defined without a chain of reinterpret_casts.
        static_assert(sizeof(proc) == sizeof(PFNGLCLEARPROC));
        std::memcpy(e.target, &proc, sizeof proc);
        if (!proc && e.version <= kRequiredVersion) {
            if (missingCount < 8) missing += std::string(missingCount ? ", " : "") + e.name;
            ++missingCount;
        }
    }
    if (missingCount > 0) {
        throw ContextError("the OpenGL library does not provide " + std::to_string(missingCount) +
                           " GL 4.5 core functions (" + missing + (missingCount > 8 ? ", ..." : "") +
                           "); the driver is too old or the backend's loader failed");
    }
}

GlFunctionCount glFunctionCount() {
    GlFunctionCount count;
    for (const Entry& e : kEntries) {
        void* proc = nullptr;
        std::memcpy(&proc, e.target, sizeof proc);
        ++count.known;
        count.loaded += proc != nullptr;
    }
    return count;
}

}  // namespace tc::gl
