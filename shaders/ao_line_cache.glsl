// Cached line ambient occlusion (gl/ao_line_cache.h): the exact cone traced AO of
// shaders/cone_tracing.glsl, evaluated once per dataset at samples along every segment and
// kAoCacheAzimuths normals around its axis, and interpolated per shaded point from the shaded
// segment id, the point's position along the segment and the normal's azimuth around the axis.
// AO from the density volume is view-independent, so the per-fragment cost drops from ~3 cones x
// ~10-20 quadrilinear 3D fetches to four byte loads. GLSL 4.50 chunk; needs line_buffers.glsl.
//
// Layout. Segment S has count >= 2 samples from index first = aoCacheSegment[S].x &
// ~kAoCacheJoinedBit on, evenly spaced from its first vertex (s = 0) to its second (s = 1). A
// segment that starts at the previous segment's end vertex (a polyline joint; kAoCacheJoinedBit
// set) shares its first sample with that segment's last, evaluated around the previous segment's
// axis with its own tube: on the tornado most segments have just their two end samples, so
// sharing halves the build. count = next first - first, + 1 if the next segment is joined.
// Sample i stores kAoCacheAzimuths AO values as unorm8 in words aoCache[2i] (azimuths 0-3) and
// aoCache[2i + 1] (4-7), azimuth k being the normal cos(phi) t + sin(phi) b at the surface point
// centre + radius * normal, phi = origin + 2 pi k / kAoCacheAzimuths, with (t, b) the
// coneTangentFrame of the segment's unit axis and origin = uintBitsToFloat(aoCacheSegment[S].y):
// the frame's tangent parallel-transported along the polyline (gl/ao_line_cache.cpp), so a
// joint's two segments agree on which azimuth is which side of the tube.
#include "line_buffers.glsl"
#include "cone_tracing.glsl"

layout(std430, binding = SSBO_AO_CACHE) readonly buffer AoCache { uint aoCache[]; };
// Per segment: x = first sample | kAoCacheJoinedBit, y = azimuth origin (float bits, radians).
layout(std430, binding = SSBO_AO_CACHE_SEGMENTS) readonly buffer AoCacheSegments { uvec2 aoCacheSegment[]; };

const int kAoCacheAzimuths = AO_CACHE_AZIMUTHS;  // multiple of 4 (gl::AoLineCache::kAzimuths)
const uint kAoCacheWords = uint(kAoCacheAzimuths / 4);
const uint kAoCacheJoinedBit = 0x80000000u;  // gl::AoLineCache::kJoinedBit

// First sample and sample count of `segment`; joined: its first sample is the previous segment's
// last; origin: its azimuth origin (radians from the coneTangentFrame tangent).
void aoCacheSamples(uint segment, out uint first, out uint count, out bool joined, out float origin)
{
    uvec2 s0 = aoCacheSegment[segment];
    uint o0 = s0.x, o1 = aoCacheSegment[segment + 1u].x;
    origin = uintBitsToFloat(s0.y);
    first = o0 & ~kAoCacheJoinedBit;
    joined = (o0 & kAoCacheJoinedBit) != 0u;
    count = (o1 & ~kAoCacheJoinedBit) - first + ((o1 & kAoCacheJoinedBit) != 0u ? 1u : 0u);
}

// The segment's unit axis (z for a degenerate segment) and the position of p along it in [0, 1].
void aoCacheSegmentAxis(vec3 a, vec3 b, vec3 p, out vec3 axis, out float s)
{
    vec3 d = b - a;
    float len2 = dot(d, d);
    axis = len2 > 0.0 ? d * inversesqrt(len2) : vec3(0.0, 0.0, 1.0);
    s = len2 > 0.0 ? clamp(dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
}

// Unit normal around `axis` at cached azimuth k from the segment's azimuth origin (what the build
// evaluates).
vec3 aoCacheNormal(vec3 axis, float origin, int k)
{
    vec3 t, b;
    coneTangentFrame(axis, t, b);
    float phi = origin + 6.28318530718 * float(k) / float(kAoCacheAzimuths);
    return cos(phi) * t + sin(phi) * b;
}

float aoCacheValue(uint sampleIndex, int k)
{
    uint word = aoCache[kAoCacheWords * sampleIndex + uint(k >> 2)];
    return float((word >> (8u * uint(k & 3))) & 0xffu) * (1.0 / 255.0);
}

// Linear in azimuth between the two neighbouring cached normals, faded to the ring's mean by
// ringWeight (aoCacheAzimuth).
float aoCacheRing(uint sampleIndex, float azimuth, float ringWeight)
{
    int k0 = int(floor(azimuth));
    float f = azimuth - float(k0);
    float ring = mix(aoCacheValue(sampleIndex, k0 % kAoCacheAzimuths),
                     aoCacheValue(sampleIndex, (k0 + 1) % kAoCacheAzimuths), f);
    if (ringWeight >= 1.0) return ring;
    vec4 sum = vec4(0.0);
    for (uint w = 0u; w < kAoCacheWords; ++w) sum += unpackUnorm4x8(aoCache[kAoCacheWords * sampleIndex + w]);
    return mix(dot(sum, vec4(1.0 / float(kAoCacheAzimuths))), ring, ringWeight);
}

// Azimuth of unit `normal` around unit `axis` in cached steps, in [0, kAoCacheAzimuths], and the
// weight of the ring against its mean: where the normal points along the axis (the pole of an
// end cap) the azimuth is undefined, so it fades to the ring's mean (full from 30 degrees off).
float aoCacheAzimuth(vec3 axis, float origin, vec3 normal, out float ringWeight)
{
    vec3 t, bt;
    coneTangentFrame(axis, t, bt);
    vec3 across = normal - dot(normal, axis) * axis;
    float acrossLength = length(across);
    float azimuth = acrossLength > 1e-6 ? atan(dot(across, bt), dot(across, t)) - origin : 0.0;
    azimuth *= float(kAoCacheAzimuths) / 6.28318530718;
    azimuth -= float(kAoCacheAzimuths) * floor(azimuth / float(kAoCacheAzimuths));
    ringWeight = clamp(acrossLength * 2.0, 0.0, 1.0);
    return azimuth;
}

// AO factor (1 = unoccluded) at `position` on segment `segment` (from a to b) with unit `normal`.
float cachedLineOcclusion(uint segment, vec3 a, vec3 b, vec3 position, vec3 normal)
{
    vec3 axis;
    float s;
    aoCacheSegmentAxis(a, b, position, axis, s);
    uint first, count;
    bool joined;
    float origin;
    aoCacheSamples(segment, first, count, joined, origin);
    // A joined segment's shared first sample was cached around the previous segment's axis, from
    // the origin transported to this one: the same azimuth reads the same side of the tube.
    float ringWeight;
    float azimuth = aoCacheAzimuth(axis, origin, normal, ringWeight);
    float x = s * float(count - 1u);
    uint j = min(uint(x), count - 2u);
    return mix(aoCacheRing(first + j, azimuth, ringWeight), aoCacheRing(first + j + 1u, azimuth, ringWeight),
               x - float(j));
}
