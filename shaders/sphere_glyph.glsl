// Transparent sphere glyphs (Staib, Grottel & Gumhold 2015): the GLSL twin of core/sphere_glyph.h
// (ray-sphere interval, density-model opacity, emission of Eq. 2 / 7, projected bounds). Same
// formulas in the same order; see the header for the derivations. GLSL 4.50 chunk, #include'd.
#ifndef TC_SPHERE_GLYPH_GLSL
#define TC_SPHERE_GLYPH_GLSL

#include "shading.glsl"

// Density models, as tc::SphereDensity.
const int kDensityConstant = 0;
const int kDensityL2 = 1;
const int kDensityHollowConstant = 2;
const int kDensityHollowL2 = 3;

struct SphereInterval {
    bool hit;
    float tNear, tFar, tClosest, dist2;
};

SphereInterval intersectSphere(vec3 origin, vec3 dir, vec3 center, float radius) {
    SphereInterval s = SphereInterval(false, 0.0, 0.0, 0.0, 0.0);
    vec3 oc = center - origin;
    s.tClosest = dot(oc, dir);
    vec3 perp = oc - s.tClosest * dir;
    s.dist2 = dot(perp, perp);
    float r2 = radius * radius;
    if (s.dist2 >= r2) return s;
    float h = sqrt(r2 - s.dist2);
    s.tFar = s.tClosest + h;
    if (s.tFar <= 0.0) return s;
    s.tNear = max(s.tClosest - h, 0.0);
    s.hit = true;
    return s;
}

float shapeIntegral(bool l2, float d2, float sn, float sf) {
    if (!l2) return sf - sn;
    return d2 * (sf - sn) + (sf * sf * sf - sn * sn * sn) / 3.0;
}

// T of tc::unitOpticalDepth: optical depth of the interval in units of the radius.
float unitOpticalDepth(int model, float k, SphereInterval s, float radius) {
    if (!s.hit) return 0.0;
    bool l2 = model == kDensityL2 || model == kDensityHollowL2;
    bool hollow = model == kDensityHollowConstant || model == kDensityHollowL2;
    float sn = s.tNear - s.tClosest, sf = s.tFar - s.tClosest;
    float integral = shapeIntegral(l2, s.dist2, sn, sf);
    float ri = k * radius;
    if (hollow && s.dist2 < ri * ri) {
        float hi = sqrt(ri * ri - s.dist2);
        float a = max(-hi, sn), b = min(hi, sf);
        if (b > a) integral -= shapeIntegral(l2, s.dist2, a, b);
    }
    float scale = l2 ? radius * radius * radius : radius;
    return max(integral / scale, 0.0);
}

// alpha = 1 - (1 - thetaMax)^(T / P) (Eq. 14 / 18 with lambda from the most opaque ray).
float sphereOpacity(float thetaMax, float T, float P) {
    if (T <= 0.0) return 0.0;
    if (thetaMax >= 1.0) return 1.0;
    return 1.0 - exp2(log2(1.0 - thetaMax) * (T / P));
}

// Eq. 2 and 7: surface term mixed with the volume emission by alpha_rv (1 = the volume emission
// alone), times A_O, plus alpha_a L_A.
vec3 sphereEmission(vec3 base, vec3 n, vec3 dir, vec3 lightDir, vec4 lightTerms, float alphaRv, float alphaA,
                    float ao, vec3 ambientLight) {
    vec3 surface = shadeBlinnPhong(base, n, dir, lightDir, lightTerms.x, lightTerms.y, lightTerms.z, lightTerms.w);
    // Staib et al. 2015, Eq. 2: L_RV = Theta ((1 - alpha_RV) L_R + alpha_RV c) (Theta: the caller's
    // premultiplication), then Eq. 7: A_O L_RV + alpha_A L_A.
    vec3 c = ao * ((1.0 - alphaRv) * surface + alphaRv * base) + alphaA * ambientLight;
    return clamp(c, vec3(0.0), vec3(1.0));
}

// tc::projectedSphereBounds with a per-axis pad: false when the sphere is behind the eye plane.
bool projectedSphereBounds(vec3 eye, vec3 f, vec3 rt, vec3 up, bool orthographic, float tanHalfFov,
                           float orthoHalfHeight, float aspect, vec3 center, float radius, vec2 pad,
                           out vec4 rect) {
    vec3 d = center - eye;
    float cx = dot(d, rt), cy = dot(d, up), cz = dot(d, f);
    rect = vec4(-1.0, -1.0, 1.0, 1.0);
    if (cz + radius <= 0.0) return false;
    if (orthographic) {
        float h = orthoHalfHeight;
        rect = vec4((cx - radius) / (h * aspect), (cy - radius) / h, (cx + radius) / (h * aspect), (cy + radius) / h);
    } else {
        if (cz <= radius) return true;
        vec2 c = vec2(cx, cy);
        vec2 len2 = c * c + cz * cz;
        vec2 len = sqrt(len2);
        vec2 s = radius / len, co = sqrt(max(len2 - radius * radius, 0.0)) / len;
        vec2 a = (c * co - cz * s) / (c * s + cz * co);
        vec2 b = (c * co + cz * s) / (cz * co - c * s);
        vec2 lo = min(a, b), hi = max(a, b);
        rect = vec4(lo.x / (tanHalfFov * aspect), lo.y / tanHalfFov, hi.x / (tanHalfFov * aspect), hi.y / tanHalfFov);
    }
    rect += vec4(-pad, pad);
    return true;
}

#endif  // TC_SPHERE_GLYPH_GLSL
