// Test shader for tests/gl/frame_uniforms_test.cpp: copies the frame uniform block
// (shaders/frame_uniforms.glsl) word by word into an SSBO, in member order: float bits as they
// are, bools as 0 / 1. With no gap between the members this is the C++ struct's bytes.
layout(local_size_x = 1) in;

#include "frame_uniforms.glsl"

layout(std430, binding = 0) writeonly buffer Words { uint words[]; };

void putVec(inout uint i, vec4 v, int n) {
    for (int k = 0; k < n; ++k) words[i++] = floatBitsToUint(v[k]);
}

void main() {
    uint i = 0u;
    for (int c = 0; c < 4; ++c) putVec(i, uViewProj[c], 4);
    putVec(i, vec4(uEye, uTanHalfFov), 4);
    putVec(i, vec4(uForward, uOrthoHalfHeight), 4);
    putVec(i, vec4(uRight, uFarDepth), 4);
    putVec(i, vec4(uUp, 0.0), 3);
    words[i++] = uOrthographic ? 1u : 0u;
    putVec(i, vec4(uLightDir, 0.0), 3);
    words[i++] = uCapClipping ? 1u : 0u;
    putVec(i, uLightTerms, 4);
    putVec(i, uNdcToTarget, 4);
    putVec(i, vec4(uViewport, uPixelOffset), 4);
    putVec(i, vec4(uTargetSize, 0.0, 0.0), 4);  // two words of std140 padding (0, as the C++ struct's)
    putVec(i, uRegionLo, 4);
    putVec(i, uRegionHi, 4);
    putVec(i, uRayBase, 4);
    putVec(i, uRayDx, 4);
    putVec(i, uRayDy, 4);
}
