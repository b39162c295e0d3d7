#pragma once
// The OpenGL 4.6 core API for tubecast code: types and enums from Khronos' glcorearb.h, and every
// core entry point as a function pointer resolved at run time by loadGlFunctions().
//
// Why a loader of our own:
// - Entry points must come from the backend that owns the current context. libOpenGL (glvnd)
//   dispatches to EGL contexts but not to OSMesa contexts, so linking libGL/libOpenGL (or using
//   libepoxy, which resolves through them) cannot drive an OSMesa context. glad, the usual
//   generated loader, is not packaged in Debian 12; gl/generate_gl_api.cmake produces the same
//   kind of list from glcorearb.h at configure time.
// - Naming scheme (as glad does): the pointers live in namespace tc::gl::fn, and a macro per
//   function (`#define glClear ::tc::gl::fn::glClear`) lets renderer code write plain
//   `glClear(...)`. The namespaced pointers have mangled symbol names, so they never collide
//   with the glClear *functions* that libGL exports when some other library (VTK) pulls it in,
//   and a stray <GL/gl.h> in the same translation unit fails to compile instead of silently
//   calling into the wrong library.
//
// Include this header instead of <GL/gl.h>, <GL/glcorearb.h> or <GL/osmesa.h> (osmesa.h drags in
// gl.h's prototypes, which the macros would turn into invalid declarations).
#if defined(__gl_h_) || defined(__GL_H__)
#error "gl/gl_api.h and <GL/gl.h> cannot share a translation unit: gl.h declares prototypes for the same names"
#endif
#if defined(GL_GLEXT_PROTOTYPES)
#error "GL_GLEXT_PROTOTYPES must not be defined: tubecast resolves GL entry points at run time"
#endif

#include <GL/glcorearb.h>

#include "gl/gl_functions_generated.h"  // build dir: extern pointers + macros, from glcorearb.h

namespace tc::gl {

// Returns the address of a GL entry point, or null: eglGetProcAddress or OSMesaGetProcAddress.
using ProcLoader = void* (*)(const char*);

// Points every GL core entry point at the implementation `loader` returns, for the backend whose
// context is (or is about to be made) current. Called by Context on creation and when switching
// backends; renderer code never calls it. Entry points the loader does not know stay null.
// Throws tc::ContextError naming the missing functions if an entry point of GL <= 4.5 is absent.
void loadGlFunctions(ProcLoader loader);

// Number of core entry points known to the loader (GL 1.0-4.6), and how many are non-null.
struct GlFunctionCount {
    int known = 0;
    int loaded = 0;
};
GlFunctionCount glFunctionCount();

}  // namespace tc::gl
