// Deferred shading of the opaque path: once per pixel, Blinn-Phong on the G-buffer (ambient and
// diffuse scaled by cone traced ambient occlusion when enabled), written as premultiplied linear
// RGBA into a float target (alpha 1 where a tube is visible, 0 elsewhere), and the AO factor.
// The camera and light from flat varyings (fullscreen.vert with FULLSCREEN_FRAME_VARYINGS).
#define FRAME_VARYINGS_IN
#include "camera.glsl"
#include "shading.glsl"
#include "frame_uniforms.glsl"
#include "ambient_occlusion.glsl"

layout(binding = TEXTURE_GBUFFER_ALBEDO) uniform sampler2D uAlbedo;
layout(binding = TEXTURE_GBUFFER_NORMAL_DEPTH) uniform sampler2D uNormalDepth;
layout(binding = TEXTURE_VISIBILITY_SEGMENTS) uniform usampler2D uSegments;  // the visibility buffer (cached AO reads it)

layout(location = 0) out vec4 outColor;
layout(location = 1) out float outAo;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 nd = texelFetch(uNormalDepth, pixel, 0);
    outAo = 1.0;
    if (isinf(nd.w)) {
        outColor = vec4(0.0);
        return;
    }
    vec4 albedo = texelFetch(uAlbedo, pixel, 0);
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    float t = uOrthographic ? nd.w : nd.w / dot(ray.dir, uForward);
    vec3 facing = dot(nd.xyz, ray.dir) <= 0.0 ? nd.xyz : -nd.xyz;
    outAo = lineAmbientOcclusion(texelFetch(uSegments, pixel, 0).r, ray.origin + t * ray.dir, facing);
    vec3 rgb = shadeBlinnPhong(albedo.rgb * outAo, nd.xyz, ray.dir, uLightDir, uLightTerms.x, uLightTerms.y,
                               uLightTerms.z, uLightTerms.w);
    outColor = vec4(rgb, 1.0);
}
