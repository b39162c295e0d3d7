// Per-segment inputs of the line fragment shaders (rounded cone, cap clipping planes, end
// colours), gathered once per segment and handed on as flat varyings. On llvmpipe every SSBO
// read in a fragment shader is a per-lane scalar load, and a segment covers tens of fragment lanes
// (4x4 blocks, mostly partial on thin billboards): reading ~30 values and building the two cap
// planes per lane cost more than the ray casting itself, while a flat varying is one broadcast
// per block (docs/performance.md, "Design notes"). GLSL 4.50 chunk; the includer #defines one of
//   SEGMENT_VARYINGS_COMPUTE  billboard_pass.comp: loadSegmentVaryings + storeSegmentRecord (the
//                             per-segment record the vertex shader copies, LineGeometry owns it);
//   SEGMENT_VARYINGS_OUT      billboard vertex / geometry shaders: the flat outputs, load, copy;
//   (neither)                 fragment shaders: the flat inputs.
// The loading modes need camera.glsl, rounded_cone.glsl and line_buffers.glsl included first.
// uCapClipping (LineGeometry::setCapClipping, the transparent paths). Outside the #if below: the
// shader library includes a file once, at its first #include, whatever #if surrounds it.
#include "frame_uniforms.glsl"
#ifndef TC_SEGMENT_VARYINGS_GLSL
#define TC_SEGMENT_VARYINGS_GLSL

struct SegmentVaryings {
    vec4 coneA;   // x0, r0
    vec4 coneB;   // x1, r1
    vec4 clip0;   // cap clipping plane at x0 (keep dot(p, xyz) + w >= 0); 0: full cap
    vec4 clip1;   // the same at x1
    vec4 color0;  // straight RGBA at x0
    vec4 color1;  // straight RGBA at x1
    vec4 axis;    // coneAxis of the cone (rounded_cone.glsl): unit axis, length
};

#if defined(SEGMENT_VARYINGS_COMPUTE) || defined(SEGMENT_VARYINGS_OUT)
#include "cap_clipping.glsl"

const uint kFirstOfPolyline = 1u;  // VertexFlag bits (core/styled_lines.h)
const uint kLastOfPolyline = 2u;

SegmentVaryings loadSegmentVaryings(uint segment) {
    uint v0 = segmentVertices[2u * segment];
    uint v1 = segmentVertices[2u * segment + 1u];
    SegmentVaryings v;
    v.coneA = positionRadius[v0];
    v.coneB = positionRadius[v1];
    v.color0 = vertexColor[v0];
    v.color1 = vertexColor[v1];
    v.axis = coneAxis(RoundedCone(v.coneA.xyz, v.coneA.w, v.coneB.xyz, v.coneB.w));
    vec4 plane0 = vec4(0.0), plane1 = vec4(0.0);
    bool clip0 = false, clip1 = false;
    if (uCapClipping) {
        // Polylines are contiguous in the vertex arrays: the neighbours are v0 - 1 and v1 + 1.
        bool hasPrev = (vertexFlags[v0] & kFirstOfPolyline) == 0u;
        bool hasNext = (vertexFlags[v1] & kLastOfPolyline) == 0u;
        vec3 prev = hasPrev ? positionRadius[v0 - 1u].xyz : v.coneA.xyz;
        vec3 next = hasNext ? positionRadius[v1 + 1u].xyz : v.coneB.xyz;
        segmentClipPlanes(prev, v.coneA.xyz, v.coneB.xyz, next, hasPrev, hasNext, plane0, plane1, clip0, clip1);
    }
    // A clipping plane always has a unit normal, so 0 is free to mean "no plane".
    v.clip0 = clip0 ? plane0 : vec4(0.0);
    v.clip1 = clip1 ? plane1 : vec4(0.0);
    return v;
}

// kSegmentRecordSize vec4 per segment, in SegmentVaryings order (LineGeometry sizes the buffer).
const uint kSegmentRecordSize = 7u;
#ifdef SEGMENT_VARYINGS_COMPUTE
layout(std430, binding = SSBO_SEGMENT_RECORDS) writeonly buffer SegmentRecords { vec4 segmentRecord[]; };

void storeSegmentRecord(uint segment, SegmentVaryings v) {
    uint r = kSegmentRecordSize * segment;
    segmentRecord[r] = v.coneA;
    segmentRecord[r + 1u] = v.coneB;
    segmentRecord[r + 2u] = v.clip0;
    segmentRecord[r + 3u] = v.clip1;
    segmentRecord[r + 4u] = v.color0;
    segmentRecord[r + 5u] = v.color1;
    segmentRecord[r + 6u] = v.axis;
}
#else
layout(std430, binding = SSBO_SEGMENT_RECORDS) readonly buffer SegmentRecords { vec4 segmentRecord[]; };

SegmentVaryings readSegmentRecord(uint segment) {
    uint r = kSegmentRecordSize * segment;
    return SegmentVaryings(segmentRecord[r], segmentRecord[r + 1u], segmentRecord[r + 2u], segmentRecord[r + 3u],
                           segmentRecord[r + 4u], segmentRecord[r + 5u], segmentRecord[r + 6u]);
}
#endif
#endif

#ifndef SEGMENT_VARYINGS_COMPUTE
#ifdef SEGMENT_VARYINGS_OUT
#define TC_SEGMENT_VARYING flat out
#else
#define TC_SEGMENT_VARYING flat in
#endif
TC_SEGMENT_VARYING vec4 vConeA;
TC_SEGMENT_VARYING vec4 vConeB;
TC_SEGMENT_VARYING vec4 vClip0;
TC_SEGMENT_VARYING vec4 vClip1;
TC_SEGMENT_VARYING vec4 vColor0;
TC_SEGMENT_VARYING vec4 vColor1;
TC_SEGMENT_VARYING vec4 vAxis;

RoundedCone varyingCone() { return RoundedCone(vConeA.xyz, vConeA.w, vConeB.xyz, vConeB.w); }

#ifdef SEGMENT_VARYINGS_OUT
void writeSegmentVaryings(SegmentVaryings v) {
    vConeA = v.coneA;
    vConeB = v.coneB;
    vClip0 = v.clip0;
    vClip1 = v.clip1;
    vColor0 = v.color0;
    vColor1 = v.color1;
    vAxis = v.axis;
}
#endif
#endif

#endif  // TC_SEGMENT_VARYINGS_GLSL
