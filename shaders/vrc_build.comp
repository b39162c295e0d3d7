// GPU build of the VRC voxel model: the twin of tc::buildVrcModel's polyline walk
// (core/vrc_model.cpp, walkPolyline / encodeGrid / packColor / packRadius), in double precision
// with the same operations in the same order, so both builds produce identical models.
// gl::buildVrcModelGpu runs it in three steps selected by defines:
//   VRC_COUNT  one invocation per polyline: pieces of the polyline -> counts[p];
//   (exclusive prefix sum of counts -> offsets, shaders/vrc_scan.comp)
//   VRC_WRITE  one invocation per polyline: pieces at slots offsets[p].., their voxel ids as sort
//              keys and the slots as values (then a stable radix sort by voxel id, so the order is
//              (voxel, slot) as on the CPU);
// The gather and header steps are in shaders/vrc_gather.comp.
// `precise` everywhere arithmetic must not be contracted into fused multiply-adds (the CPU build
// does not fuse either).
layout(local_size_x = 64) in;

layout(std430, binding = SSBO_POSITION_RADIUS) readonly buffer PositionRadius { vec4 positionRadius[]; };
layout(std430, binding = SSBO_VERTEX_COLORS) readonly buffer Colors { vec4 vertexColor[]; };
layout(std430, binding = SSBO_POLYLINE_IDS) readonly buffer PolylineIds { uint polylineId[]; };
layout(std430, binding = SSBO_VRC_POLYLINES) readonly buffer Polylines { uvec2 polylineRange[]; };  // first, last vertex
layout(std430, binding = SSBO_VRC_COUNTS) buffer Counts { uint counts[]; };     // VRC_COUNT: out; VRC_WRITE: offsets in
layout(std430, binding = SSBO_VRC_KEYS) writeonly buffer Keys { uint keys[]; };
layout(std430, binding = SSBO_VRC_VALUES) writeonly buffer Values { uint values[]; };
#ifdef QUANTIZED
layout(std430, binding = SSBO_VRC_RAW_PIECES) writeonly buffer Raw { uvec4 raw[]; };
#else
struct VrcExactPiece {
    vec4 a;
    vec4 b;
    vec4 color;
    uvec4 info;
};
layout(std430, binding = SSBO_VRC_RAW_PIECES) writeonly buffer Raw { VrcExactPiece raw[]; };
#endif

uniform uint uPolylines;
uniform ivec3 uGridSize;
uniform dvec3 uOrigin;      // double(grid.origin)
uniform double uVoxelSize;  // double(grid.voxelSize)
uniform int uQuantization;
uniform float uMaxRadius;

const uint kInteriorFace = 6u;

ivec2 planeAxes(int axis) { return axis == 0 ? ivec2(1, 2) : (axis == 1 ? ivec2(0, 2) : ivec2(0, 1)); }

dvec3 gridPos(uint i) {
    precise dvec3 p = (dvec3(positionRadius[i].xyz) - uOrigin) / uVoxelSize;
    precise dvec3 hi = dvec3(uGridSize) * (1.0LF - 1e-12LF);
    return clamp(p, dvec3(0.0LF), hi);
}

uint encodeGrid(ivec3 v, uint face, dvec3 p) {
    int q = uQuantization;
    precise dvec3 local = p - dvec3(v);
    if (face == kInteriorFace) {
        int m = min(q, 16);
        ivec3 cell = clamp(ivec3(floor(local * double(m))), ivec3(0), ivec3(m - 1));
        return (face << 13u) | uint((cell.z * m + cell.y) * m + cell.x);
    }
    ivec2 plane = planeAxes(int(face / 2u));
    int u = clamp(int(floor(local[plane.x] * double(q))), 0, q - 1);
    int w = clamp(int(floor(local[plane.y] * double(q))), 0, q - 1);
    return (face << 13u) | uint(w * q + u);
}

// std::lround(x) for x >= 0 (x + 0.5 in double cannot round up to the next integer).
uint roundHalfUp(float x) { return uint(floor(double(x) + 0.5LF)); }

uint packColor(vec4 c) {
    uint bits = 0u;
    for (int i = 0; i < 4; ++i) {
        precise float v = clamp(c[i], 0.0, 1.0) * 255.0;
        bits |= roundHalfUp(v) << uint(8 * i);
    }
    return bits;
}

uint packRadius(float r) {
    precise float f = uMaxRadius > 0.0 ? clamp(r / uMaxRadius, 0.0, 1.0) : 0.0;
    precise float s = f * 65535.0;
    return roundHalfUp(s);
}

// The piece being built (walkPolyline's RawPiece).
ivec3 pv;
dvec3 pa;
uint pFaceA;
float pRa;
vec4 pCa;
bool pMoved;
uint pLine;
uint pSlot;
uint pCount;

void emit(dvec3 b, uint faceB, float rb, vec4 cb) {
    // Crossings through an edge or corner visit a neighbour for no distance: nothing to draw.
    if (!(pMoved || pa != b)) return;
#ifdef VRC_WRITE
    uint slot = pSlot + pCount;
    keys[slot] = uint((pv.z * uGridSize.y + pv.y) * uGridSize.x + pv.x);
    values[slot] = slot;
    precise vec4 color = 0.5 * (pCa + cb);
    uint flags = (pFaceA == kInteriorFace ? 1u : 0u) | (faceB == kInteriorFace ? 2u : 0u);
#ifdef QUANTIZED
    uint ends = encodeGrid(pv, pFaceA, pa) | (encodeGrid(pv, faceB, b) << 16u);
    raw[slot] = uvec4(ends, pLine, packColor(color), packRadius(pRa) | (packRadius(rb) << 16u));
#else
    precise dvec3 wa = uOrigin + pa * uVoxelSize;
    precise dvec3 wb = uOrigin + b * uVoxelSize;
    raw[slot] = VrcExactPiece(vec4(vec3(wa), pRa), vec4(vec3(wb), rb), color, uvec4(pLine, flags, 0u, 0u));
#endif
#endif
    ++pCount;
}

void main() {
    uint p = gl_GlobalInvocationID.x;
    if (p >= uPolylines) return;
    uint first = polylineRange[p].x, last = polylineRange[p].y;
    pLine = polylineId[first];
    pCount = 0u;
#ifdef VRC_WRITE
    pSlot = counts[p];
#endif
    dvec3 a = gridPos(first);
    ivec3 v = clamp(ivec3(floor(a)), ivec3(0), uGridSize - 1);
    pv = v;
    pa = a;
    pFaceA = kInteriorFace;
    pRa = positionRadius[first].w;
    pCa = vertexColor[first];
    pMoved = false;

    for (uint i = first; i < last; ++i) {
        dvec3 b = gridPos(i + 1u);
        precise dvec3 d = b - a;
        double segLength = length(d);
        vec4 ra4 = positionRadius[i], rb4 = positionRadius[i + 1u];
        vec4 ca = vertexColor[i], cb = vertexColor[i + 1u];
        ivec3 stepDir;
        dvec3 invD;
        for (int k = 0; k < 3; ++k) {
            stepDir[k] = d[k] > 0.0LF ? 1 : (d[k] < 0.0LF ? -1 : 0);
            invD[k] = d[k] != 0.0LF ? 1.0LF / d[k] : 0.0LF;
        }
        double s = 0.0LF;
        for (;;) {
            double sNext = 1.0LF;
            int axis = -1;
            for (int k = 0; k < 3; ++k) {
                if (stepDir[k] == 0) continue;
                double face = double(stepDir[k] > 0 ? v[k] + 1 : v[k]);
                precise double sk = (face - a[k]) * invD[k];
                if (sk < sNext) {
                    sNext = sk;
                    axis = k;
                }
            }
            sNext = max(sNext, s);
            if (sNext > s && segLength > 0.0LF) pMoved = true;
            if (axis < 0) break;
            ivec3 next = v;
            next[axis] += stepDir[axis];
            if (next[axis] < 0 || next[axis] >= uGridSize[axis]) break;
            precise dvec3 x = a + sNext * d;
            x[axis] = double(stepDir[axis] > 0 ? v[axis] + 1 : v[axis]);
            // As the CPU: the radius difference in float, the interpolation in double.
            precise float dr = rb4.w - ra4.w;
            precise double rd = double(ra4.w) + double(dr) * sNext;
            float r = float(rd);
            float sf = float(sNext);
            // glm::mix's formula, unfused.
            precise vec4 c = ca * (1.0 - sf) + cb * sf;
            emit(x, uint(2 * axis + (stepDir[axis] > 0 ? 1 : 0)), r, c);
            v = next;
            pv = v;
            pa = x;
            pFaceA = uint(2 * axis + (stepDir[axis] > 0 ? 0 : 1));
            pRa = r;
            pCa = c;
            pMoved = false;
            s = sNext;
        }
        a = b;
    }
    emit(a, kInteriorFace, positionRadius[last].w, vertexColor[last]);
#ifdef VRC_COUNT
    counts[p] = pCount;
#endif
}
