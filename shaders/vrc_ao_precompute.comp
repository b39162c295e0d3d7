// Per-voxel spherical ambient occlusion of the voxel model (Kanzler, Rautenhaus & Westermann 2019,
// Sec. 5.3, second approach; Sec. 6.4: 100 rays per voxel, one voxel steps): at every voxel centre
// 1 - the mean occlusion of uVrcSphereRays density rays evenly over the sphere
// (shaders/vrc_lighting.glsl; core/vrc_lighting.h vrcSphereAmbientOcclusion is the CPU twin).
// Computed once per model by gl/vrc_renderer.cpp, read trilinearly per hit. Only voxels whose
// 3x3x3 block holds pieces (the header's neighbourhood bit) are computed: a hit's trilinear read
// touches no others. The rest is 1.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

uniform ivec3 uGridSize;
uniform vec3 uGridOrigin;
uniform float uVoxelSize;
uniform int uVrcSphereRays;

#include "vrc_lighting.glsl"

layout(std430, binding = SSBO_VRC_HEADER) readonly buffer VrcHeader { uvec2 vrcVoxels[]; };
layout(r16f, binding = IMAGE_VRC_AO_VOLUME) uniform writeonly image3D uAoOut;

void main() {
    ivec3 v = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(v, uGridSize))) return;
    float ao = 1.0;
    if ((vrcVoxels[(v.z * uGridSize.y + v.y) * uGridSize.x + v.x].y & 0x80000000u) != 0u) {
        VrcOwnLine none = VrcOwnLine(vec3(0.0), vec3(0.0, 0.0, 1.0), 0.0);
        float occlusion = 0.0;
        for (int i = 0; i < uVrcSphereRays; ++i)
            occlusion += vrcDensityRayOcclusion(vec3(v) + 0.5, vrcSphereDirection(i, uVrcSphereRays), none);
        ao = 1.0 - occlusion / float(uVrcSphereRays);
    }
    imageStore(uAoOut, v, vec4(ao));
}
