// Ray / rounded-cone interval and signed distance: the GPU twin of core/rounded_cone.cpp (same
// math, names and edge cases; keep them in lock-step). GLSL 4.50 chunk, #include'd after
// camera.glsl (for Ray).
#ifndef TC_ROUNDED_CONE_GLSL
#define TC_ROUNDED_CONE_GLSL

#ifndef TC_CAMERA_GLSL
#error "rounded_cone.glsl needs camera.glsl (struct Ray) included first"
#endif

struct RoundedCone {
    vec3 x0;
    float r0;
    vec3 x1;
    float r1;
};

// Whole entry/exit interval along the ray (t may be negative); outward unit normals. On a miss
// hit = false and the other fields are 0.
struct ConeInterval {
    bool hit;
    float tIn;
    float tOut;
    vec3 nIn;
    vec3 nOut;
};

// Parameters beyond this are "no root" (a linear equation's root at infinity).
const float kConeHuge = 1e18;
const float kConeFar = 1e30;

// Sphere piece of intersectRoundedCone: discriminant from the perpendicular offset. The pieces
// hand on unnormalized normals: intersectRoundedCone normalizes only the two it returns (on
// llvmpipe every candidate's normalize runs for every lane, taken or not), which gives the same
// bits as normalizing each candidate.
void tcConeSphere(vec3 oc, float r, vec3 dir, inout bool hit, inout float tIn, inout float tOut,
                  inout vec3 nIn, inout vec3 nOut) {
    float b = dot(oc, dir);
    vec3 perp = oc - b * dir;
    float h = r * r - dot(perp, perp);
    if (h < 0.0) return;
    float sq = sqrt(h);
    float ta = -b - sq, tb = -b + sq;
    hit = true;
    if (ta < tIn) { tIn = ta; nIn = perp - sq * dir; }
    if (tb > tOut) { tOut = tb; nOut = perp + sq * dir; }
}

// Lateral piece of intersectRoundedCone (see there).
void tcConeLateral(float t, bool entry, vec3 oa, vec3 dir, vec3 u, float w, float m2, float c2, float ac,
                   float L, inout bool hit, inout float tIn, inout float tOut, inout vec3 nIn,
                   inout vec3 nOut) {
    float yc = w + t * m2;
    float ya = yc + c2 * ac;
    if (!(ya >= 0.0 && ya <= L * c2)) return;
    vec3 n = c2 * (oa + t * dir) - u * yc;
    hit = true;
    if (entry && t < tIn) { tIn = t; nIn = n; }
    if (!entry && t > tOut) { tOut = t; nOut = n; }
}

// The cone's unit axis and length, (u, L), exactly as intersectRoundedCone needs them. Passes that
// test one segment in many fragments compute it once per segment (shaders/segment_varyings.glsl):
// a square root and three divisions less per fragment, same bits.
vec4 coneAxis(RoundedCone c) {
    vec3 ba = c.x1 - c.x0;
    float L = length(ba);
    return vec4(L > 0.0 ? ba / L : vec3(0.0), L);
}

// Union of sphere 0, sphere 1 and the lateral surface of the common tangent cone (I. Quilez'
// rounded-cone intersector extended to both roots), solved around the axis point closest to the
// ray for float precision. ray.dir must be unit length; radii > 0; axis = coneAxis(c).
ConeInterval intersectRoundedCone(Ray ray, RoundedCone c, vec4 axis) {
    vec3 o = ray.origin, dir = ray.dir;
    float L = axis.w;
    float rr = c.r0 - c.r1;
    vec3 u = axis.xyz;
    float m2 = dot(dir, u);
    vec3 uxd = cross(u, dir);
    float sin2 = dot(uxd, uxd);

    vec3 w0 = o - c.x0;
    float ac = 0.0;
    if (sin2 > 1e-6) ac = clamp((dot(w0, u) - m2 * dot(w0, dir)) / sin2, 0.0, L);
    vec3 xc = c.x0 + ac * u;
    float t0 = dot(xc - o, dir);
    vec3 oa = (o - xc) + t0 * dir;

    float tIn = kConeFar, tOut = -kConeFar;
    vec3 nIn = vec3(0.0), nOut = vec3(0.0);
    bool hit = false;

    tcConeSphere(oa + ac * u, c.r0, dir, hit, tIn, tOut, nIn, nOut);
    tcConeSphere(oa - (L - ac) * u, c.r1, dir, hit, tIn, tOut, nIn, nOut);

    if (L > abs(rr)) {
        float s = rr / L;
        float c2 = (1.0 - s) * (1.0 + s);
        float rc = c.r0 - s * ac;
        float m1 = dot(oa, u), m3 = dot(oa, dir);
        float k2 = sin2 - s * s;
        float w = m1 - rc * s;
        float k1 = c2 * m3 - m2 * w;
        float k0 = c2 * (dot(oa, oa) - rc * rc) - w * w;
        float h = k1 * k1 - k0 * k2;
        if (h >= 0.0) {
            float sq = sqrt(h);
            float q = -(k1 + (k1 >= 0.0 ? sq : -sq));
            bool validA = abs(q) < kConeHuge * abs(k2);
            bool validB = abs(k0) < kConeHuge * abs(q);
            float tA = validA ? q / k2 : 0.0;
            float tB = validB ? k0 / q : 0.0;
            bool aIsEntry = k1 >= 0.0;
            if (validA) tcConeLateral(tA, aIsEntry, oa, dir, u, w, m2, c2, ac, L, hit, tIn, tOut, nIn, nOut);
            if (validB) tcConeLateral(tB, !aIsEntry, oa, dir, u, w, m2, c2, ac, L, hit, tIn, tOut, nIn, nOut);
        }
    }

    ConeInterval result;
    result.hit = false;
    result.tIn = 0.0;
    result.tOut = 0.0;
    result.nIn = vec3(0.0);
    result.nOut = vec3(0.0);
    if (!hit) return result;
    if (tOut < tIn) {
        if (tOut == -kConeFar) { tOut = tIn; nOut = nIn; }
        else if (tIn == kConeFar) { tIn = tOut; nIn = nOut; }
        else { float m = 0.5 * (tIn + tOut); tIn = m; tOut = m; }
    }
    result.hit = true;
    result.tIn = t0 + tIn;
    result.tOut = t0 + tOut;
    result.nIn = normalize(nIn);
    result.nOut = normalize(nOut);
    return result;
}

ConeInterval intersectRoundedCone(Ray ray, RoundedCone c) {
    return intersectRoundedCone(ray, c, coneAxis(c));
}

// Signed distance: exact outside, negative inside.
float sdRoundedCone(vec3 p, RoundedCone c) {
    vec3 ba = c.x1 - c.x0;
    float L = length(ba);
    float rr = c.r0 - c.r1;
    if (!(L > abs(rr))) return c.r0 >= c.r1 ? length(p - c.x0) - c.r0 : length(p - c.x1) - c.r1;
    vec3 u = ba / L;
    float s = rr / L;
    float cs = sqrt((1.0 - s) * (1.0 + s));
    vec3 pa = p - c.x0;
    float y = dot(pa, u);
    float rho = length(pa - y * u);
    float k = y * cs - rho * s;
    if (k < 0.0) return length(pa) - c.r0;
    if (k > L * cs) return length(p - c.x1) - c.r1;
    return y * s + rho * cs - c.r0;
}

#endif  // TC_ROUNDED_CONE_GLSL
