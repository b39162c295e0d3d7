// GLSL twin of core/sort_keys.h: order-preserving float -> uint keys and the per-segment sort
// distance. Every result is `precise` so the compiler neither fuses multiply-adds into FMAs nor
// reorders them: the CPU (core/sort_keys.cpp) computes the same IEEE operations in the same order,
// and the two keys are equal bit for bit.

uint sortKeyFromFloat(float value)
{
    uint bits = floatBitsToUint(value);
    return (bits & 0x80000000u) != 0u ? ~bits : (bits | 0x80000000u);
}

float floatFromSortKey(uint key)
{
    return uintBitsToFloat((key & 0x80000000u) != 0u ? (key & 0x7FFFFFFFu) : ~key);
}

float sortDot3(vec3 a, vec3 b)
{
    precise float xy = a.x * b.x + a.y * b.y;
    precise float r = xy + a.z * b.z;
    return r;
}

// Minimum distance from eye to the segment [x0, x1].
float segmentDistance(vec3 eye, vec3 x0, vec3 x1)
{
    precise vec3 d = x1 - x0;
    precise vec3 e = eye - x0;
    precise float dd = sortDot3(d, d);
    precise float t = 0.0;
    if (dd > 0.0)
        t = min(max(sortDot3(e, d) / dd, 0.0), 1.0);
    precise vec3 closest = e - t * d;
    precise float r = sqrt(sortDot3(closest, closest));
    return r;
}

// Minimum view depth along the unit `forward` over the segment (at one of its end points).
float segmentDepth(vec3 eye, vec3 forward, vec3 x0, vec3 x1)
{
    precise float a = sortDot3(x0 - eye, forward);
    precise float b = sortDot3(x1 - eye, forward);
    return min(a, b);
}
