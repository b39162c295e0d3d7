// Last steps of the VRC GPU build (gl::buildVrcModelGpu), after the stable radix sort of
// (voxel id, slot) pairs, selected by defines:
//   VRC_GATHER     one invocation per piece: pieces[i] = raw[slot of i], pieceVoxel[i] = voxel id,
//                  the header's offset at the start of each voxel's run and its end in runEnd;
//   VRC_HEADER     one invocation per voxel: count = runEnd - offset;
//   VRC_NEIGHBORS  one invocation per voxel: the neighbourhood bit (core/vrc_model.h).
layout(local_size_x = 64) in;

layout(std430, binding = SSBO_VRC_HEADER) buffer Header { uvec2 header[]; };
layout(std430, binding = SSBO_VRC_RUN_END) buffer RunEnd { uint runEnd[]; };
layout(std430, binding = SSBO_VRC_KEYS) readonly buffer Keys { uint keys[]; };
layout(std430, binding = SSBO_VRC_VALUES) readonly buffer Values { uint values[]; };
#ifdef QUANTIZED
layout(std430, binding = SSBO_VRC_RAW_PIECES) readonly buffer Raw { uvec4 raw[]; };
layout(std430, binding = SSBO_VRC_GATHERED_PIECES) writeonly buffer Pieces { uvec4 pieces[]; };
#else
struct VrcExactPiece {
    vec4 a;
    vec4 b;
    vec4 color;
    uvec4 info;
};
layout(std430, binding = SSBO_VRC_RAW_PIECES) readonly buffer Raw { VrcExactPiece raw[]; };
layout(std430, binding = SSBO_VRC_GATHERED_PIECES) writeonly buffer Pieces { VrcExactPiece pieces[]; };
#endif
layout(std430, binding = SSBO_VRC_PIECE_VOXEL) writeonly buffer PieceVoxel { uint pieceVoxel[]; };

uniform uint uCount;  // pieces (VRC_GATHER) or voxels
uniform ivec3 uGridSize;
// Dispatches are capped at 65535 groups along x; larger counts use y.
uint invocation() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x; }

void main() {
    uint i = invocation();
    if (i >= uCount) return;
#ifdef VRC_GATHER
    uint key = keys[i];
    pieces[i] = raw[values[i]];
    pieceVoxel[i] = key;
    if (i == 0u || keys[i - 1u] != key) header[key].x = i;
    if (i + 1u == uCount || keys[i + 1u] != key) runEnd[key] = i + 1u;
#endif
#ifdef VRC_HEADER
    uint end = runEnd[i];
    header[i].y = end > 0u ? end - header[i].x : 0u;
#endif
#ifdef VRC_NEIGHBORS
    ivec3 v = ivec3(int(i % uint(uGridSize.x)), int(i / uint(uGridSize.x) % uint(uGridSize.y)),
                    int(i / uint(uGridSize.x) / uint(uGridSize.y)));
    bool occupied = false;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                ivec3 n = v + ivec3(dx, dy, dz);
                if (any(lessThan(n, ivec3(0))) || any(greaterThanEqual(n, uGridSize))) continue;
                occupied = occupied || (header[(n.z * uGridSize.y + n.y) * uGridSize.x + n.x].y & 0x7FFFFFFFu) != 0u;
            }
    if (occupied) header[i].y |= 0x80000000u;
#endif
}
