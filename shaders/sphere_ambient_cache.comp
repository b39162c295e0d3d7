// The view-independent part of the sphere glyphs' ambient terms, once per data frame: A_O and L_A
// (shaders/sphere_ambient.glsl, the exact per-point cone tracing) at the six points of each
// sphere's surface whose normals are the coordinate axes, stored as an "ambient cube" (Mitchell,
// McTaggart & Green 2006) that sphere.frag blends with the squared normal components. One
// invocation per (sphere, face): 6 x particles cone sets per data frame instead of 3 cones per
// covered fragment per frame (docs/performance.md, "Particles as sphere glyphs").
layout(local_size_x = 64) in;

#include "sphere_ambient.glsl"

layout(std430, binding = SSBO_SPHERE_CENTER_RADIUS) readonly buffer CenterRadius { vec4 centerRadius[]; };
layout(std430, binding = SSBO_SPHERE_AMBIENT_CUBE) writeonly buffer AmbientCube { uint ambientCube[]; };  // 6 per sphere

uniform uint uFirst;  // first (sphere, face) item of this dispatch
uniform uint uCount;  // 6 x spheres

const vec3 kFaceNormals[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0),
                                     vec3(0, 0, 1), vec3(0, 0, -1));

void main() {
    uint item = uFirst + gl_GlobalInvocationID.x;
    if (item >= uCount) return;
    vec4 cr = centerRadius[item / 6u];
    vec3 n = kFaceNormals[item % 6u];
    float ao;
    vec3 light;
    sphereAmbient(cr.xyz + cr.w * n, n, ao, light);
    ambientCube[item] = packUnorm4x8(vec4(light, ao));
}
