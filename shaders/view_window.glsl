// The render target as a window of the full image (core/tiling.h ImageWindow; set by
// gl/view_window.cpp): a tile and/or a jittered sample position. Rays use the full image's
// uViewport and full-image window coordinates gl_FragCoord.xy + uPixelOffset; geometry projected
// to full-image NDC reaches the target through targetNdc. A full window has uPixelOffset = 0 and
// uNdcToTarget = (1, 1, 0, 0), which leave every value bit-for-bit unchanged. GLSL 4.50 chunk.
#ifndef TC_VIEW_WINDOW_GLSL
#define TC_VIEW_WINDOW_GLSL

uniform vec2 uPixelOffset;  // full-image window coordinate of the target's origin (y up)
uniform vec4 uNdcToTarget;  // full-image NDC -> target NDC: ndc * xy + zw
uniform vec2 uTargetSize;   // the render target in pixels

vec2 targetNdc(vec2 ndc) { return ndc * uNdcToTarget.xy + uNdcToTarget.zw; }

#endif  // TC_VIEW_WINDOW_GLSL
