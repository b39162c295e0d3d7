// Cap clipping (Groß & Gumhold 2020, Sect. 5.4): the GPU twin of core/cap_clipping.cpp (same math,
// names and edge cases; keep them in lock-step). The rule and its limits are documented in
// core/cap_clipping.h. GLSL 4.50 chunk, #include'd after camera.glsl (Ray) and rounded_cone.glsl
// (ConeInterval). For the transparent fragment shaders (k-buffer, depth peeling).
#ifndef TC_CAP_CLIPPING_GLSL
#define TC_CAP_CLIPPING_GLSL

#ifndef TC_ROUNDED_CONE_GLSL
#error "cap_clipping.glsl needs camera.glsl and rounded_cone.glsl included first"
#endif

// Unit direction of d, or 0 for a (numerically) zero-length segment.
vec3 tcDirectionOrZero(vec3 d) {
    float l2 = dot(d, d);
    return l2 > 1e-24 ? d / sqrt(l2) : vec3(0.0);
}

// Unit normal of the joint plane at x between the segments (prev, x) and (x, next), oriented
// along the polyline (the segment after keeps the positive side); 0 when there is no plane. A fold
// (|sum| < 1e-4) falls back to the previous segment's direction.
vec3 jointPlaneNormal(vec3 prev, vec3 x, vec3 next) {
    vec3 dPrev = tcDirectionOrZero(x - prev);
    vec3 dNext = tcDirectionOrZero(next - x);
    vec3 s = dPrev + dNext;
    float l2 = dot(s, s);
    if (l2 < 1e-8) return dPrev;
    return s / sqrt(l2);
}

// Planes of the segment (x0, x1) as in tc::segmentClipPlanes: xPrev / xNext are the polyline
// neighbours of x0 / x1, used only when hasPrev / hasNext (not First/LastOfPolyline). A point p is
// kept when dot(plane.xyz, p) + plane.w >= 0; clip0 / clip1 false means a full cap.
void segmentClipPlanes(vec3 xPrev, vec3 x0, vec3 x1, vec3 xNext, bool hasPrev, bool hasNext, out vec4 plane0,
                       out vec4 plane1, out bool clip0, out bool clip1) {
    plane0 = vec4(0.0);
    plane1 = vec4(0.0);
    clip0 = false;
    clip1 = false;
    if (hasPrev) {
        vec3 n = jointPlaneNormal(xPrev, x0, x1);
        if (n != vec3(0.0)) { plane0 = vec4(n, -dot(n, x0)); clip0 = true; }
    }
    if (hasNext) {
        vec3 n = jointPlaneNormal(x0, x1, xNext);
        if (n != vec3(0.0)) { plane1 = vec4(-n, dot(n, x1)); clip1 = true; }
    }
}

// A rounded-cone interval after clipping (tc::ClippedInterval).
struct ClippedInterval {
    bool hit;
    float tEntry;
    float tExit;
    bool entryOnSurface;
    bool exitOnSurface;
    vec3 nEntry;
    vec3 nExit;
};

// Restricts [a, b] to the plane's half-space; false when the plane removes the whole ray (a ray
// parallel to the plane is kept or removed as a whole by its origin's side).
bool tcClipByPlane(vec4 plane, Ray ray, inout float a, inout float b, inout bool aOnPlane, inout bool bOnPlane) {
    float f0 = dot(plane.xyz, ray.origin) + plane.w;
    float fd = dot(plane.xyz, ray.dir);
    if (fd == 0.0) return f0 >= 0.0;
    float t = -f0 / fd;
    if (fd > 0.0) {
        if (t > a) { a = t; aOnPlane = true; }
    } else {
        if (t < b) { b = t; bOnPlane = true; }
    }
    return true;
}

ClippedInterval clipInterval(Ray ray, ConeInterval cone, vec4 plane0, vec4 plane1, bool clip0, bool clip1) {
    ClippedInterval r;
    r.hit = false;
    r.tEntry = 0.0;
    r.tExit = 0.0;
    r.entryOnSurface = false;
    r.exitOnSurface = false;
    r.nEntry = vec3(0.0);
    r.nExit = vec3(0.0);
    if (!cone.hit) return r;
    float a = cone.tIn, b = cone.tOut;
    bool aOnPlane = false, bOnPlane = false;
    if (clip0 && !tcClipByPlane(plane0, ray, a, b, aOnPlane, bOnPlane)) return r;
    if (clip1 && !tcClipByPlane(plane1, ray, a, b, aOnPlane, bOnPlane)) return r;
    if (!(a < b) && (aOnPlane || bOnPlane)) return r;
    r.hit = true;
    r.tEntry = a;
    r.tExit = b;
    r.entryOnSurface = !aOnPlane;
    r.exitOnSurface = !bOnPlane;
    r.nEntry = aOnPlane ? vec3(0.0) : cone.nIn;
    r.nExit = bOnPlane ? vec3(0.0) : cone.nOut;
    return r;
}

// The fragment rule of the transparent paths (core/cap_clipping.h): true, with t > 0 and the
// tube's outward normal n, when this segment contributes a fragment on this ray. Without cap
// clipping pass clip0 = clip1 = false (then: tIn if > 0, else tOut if > 0).
bool segmentFragment(Ray ray, ConeInterval cone, vec4 plane0, vec4 plane1, bool clip0, bool clip1, out float t,
                     out vec3 n) {
    t = 0.0;
    n = vec3(0.0);
    ClippedInterval c = clipInterval(ray, cone, plane0, plane1, clip0, clip1);
    if (!c.hit) return false;
    if (c.tEntry > 0.0) {
        if (!c.entryOnSurface) return false;
        t = c.tEntry;
        n = c.nEntry;
        return true;
    }
    if (c.tExit > 0.0 && c.exitOnSurface) {
        t = c.tExit;
        n = c.nExit;
        return true;
    }
    return false;
}

#endif  // TC_CAP_CLIPPING_GLSL
