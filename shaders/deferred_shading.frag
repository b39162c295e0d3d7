// Deferred shading of the opaque path: once per pixel, Blinn-Phong on the G-buffer, written as
// premultiplied linear RGBA into a float target (alpha 1 where a tube is visible, 0 elsewhere).
#include "camera.glsl"
#include "shading.glsl"
#include "frame_uniforms.glsl"

layout(binding = 0) uniform sampler2D uAlbedo;
layout(binding = 1) uniform sampler2D uNormalDepth;
uniform vec3 uLightDir;    // world space, toward the light
uniform vec4 uLightTerms;  // ambient, diffuse, specular, shininess

layout(location = 0) out vec4 outColor;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 nd = texelFetch(uNormalDepth, pixel, 0);
    if (isinf(nd.w)) {
        outColor = vec4(0.0);
        return;
    }
    vec4 albedo = texelFetch(uAlbedo, pixel, 0);
    Ray ray = pixelRay(frameCamera(), gl_FragCoord.xy);
    vec3 rgb = shadeBlinnPhong(albedo.rgb, nd.xyz, ray.dir, uLightDir, uLightTerms.x, uLightTerms.y,
                               uLightTerms.z, uLightTerms.w);
    outColor = vec4(rgb, 1.0);
}
