// View-aligned billboard of one rounded cone (Groß & Gumhold 2020, Sect. 5.1): the GPU twin of
// core/billboard.cpp (same math, names and edge cases; keep them in lock-step; the shapes are
// described in core/billboard.h). GLSL 4.50 chunk, #include'd after rounded_cone.glsl (for
// RoundedCone and sdRoundedCone). BILLBOARD_RECTANGLE selects BillboardShape::Rectangle
// (render.billboard_shape "rectangle"); the default is the paper's quad (Eq. 1-10).
#ifndef TC_BILLBOARD_GLSL
#define TC_BILLBOARD_GLSL

#ifndef TC_ROUNDED_CONE_GLSL
#error "billboard.glsl needs rounded_cone.glsl included first"
#endif

struct Billboard {
    vec2 ndc[4];      // corners in triangle-strip order; gl_Position = vec4(ndc[i], 0.0, 1.0)
    bool fullscreen;  // the eye is in or next to the cone, or the cone crosses the eye plane
    bool culled;      // entirely behind the eye plane: a zero-area quad off screen
};

Billboard tcBillboardFullscreen() {
    Billboard bb;
    bb.ndc[0] = vec2(-1.0, -1.0);
    bb.ndc[1] = vec2(1.0, -1.0);
    bb.ndc[2] = vec2(-1.0, 1.0);
    bb.ndc[3] = vec2(1.0, 1.0);
    bb.fullscreen = true;
    bb.culled = false;
    return bb;
}

vec3 tcAnyPerpendicular(vec3 v) {
    vec3 a = abs(v.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    return normalize(cross(v, a));
}

// The eye's tangent-cone radius around sphere (x, r) (Eq. 2-3); r when orthographic. False when
// the eye is (within rounding) on the sphere.
bool tcTangentRadius(vec3 x, float r, vec3 eye, bool orthographic, out float rp) {
    rp = r;
    if (orthographic) return true;
    float D = length(eye - x);
    float k = (D - r) * (D + r);
    if (!(k > 1e-8 * D * D)) return false;
    rp = D * r / sqrt(k);
    return true;
}

// Projects p; false when p is at or behind the eye plane relative to referenceW (clip w).
bool tcProject(mat4 viewProj, vec3 p, float referenceW, out vec2 ndc) {
    vec4 c = viewProj * vec4(p, 1.0);
    ndc = c.xy / c.w;
    return c.w > 1e-6 * referenceW;
}

bool tcRectangleQuad(RoundedCone c, mat4 viewProj, vec3 eye, bool orthographic, vec3 forward, out vec2 q[4]) {
    vec3 ba = c.x1 - c.x0;
    vec2 pts[8];
    vec2 centre[2];
    for (int i = 0; i < 2; ++i) {
        vec3 xi = i == 0 ? c.x0 : c.x1;
        float ri = i == 0 ? c.r0 : c.r1;
        vec3 di = eye - xi;
        vec3 v = orthographic ? -forward : di / length(di);
        float rp;
        if (!tcTangentRadius(xi, ri, eye, orthographic, rp)) return false;
        // b, then a = b x v: orthonormal even when the view runs nearly along the axis.
        vec3 b = cross(v, ba);
        float lb = length(b);
        b = lb > 1e-6 * length(ba) && lb > 0.0 ? b / lb : tcAnyPerpendicular(v);
        vec3 a = cross(b, v);
        vec4 cc = viewProj * vec4(xi, 1.0);
        centre[i] = cc.xy / cc.w;
        for (int k = 0; k < 4; ++k) {
            float sa = (k & 1) != 0 ? 1.0 : -1.0, sb = (k & 2) != 0 ? 1.0 : -1.0;
            if (!tcProject(viewProj, xi + (sa * rp) * a + (sb * rp) * b, cc.w, pts[4 * i + k])) return false;
        }
    }

    vec2 e = centre[1] - centre[0];
    float le = length(e);
    float extent = length(pts[0] - pts[3]) + length(pts[4] - pts[7]);
    e = le > 1e-6 * extent && le > 0.0 ? e / le : vec2(1.0, 0.0);
    vec2 f = vec2(-e.y, e.x);
    float loE = 3.0e38, hiE = -3.0e38, loF = 3.0e38, hiF = -3.0e38;
    for (int k = 0; k < 8; ++k) {
        float pe = dot(pts[k], e), pf = dot(pts[k], f);
        loE = min(loE, pe);
        hiE = max(hiE, pe);
        loF = min(loF, pf);
        hiF = max(hiF, pf);
    }
    q[0] = loE * e + loF * f;
    q[1] = hiE * e + loF * f;
    q[2] = loE * e + hiF * f;
    q[3] = hiE * e + hiF * f;
    return true;
}

// Groß & Gumhold 2020, Eq. 1-10; degenerate (and false) when the view runs nearly along the axis.
bool tcGross2020Quad(RoundedCone cone, mat4 viewProj, vec3 eye, bool orthographic, vec3 forward, out vec2 q[4],
                     out bool degenerate) {
    degenerate = false;
    // Sect. 5.1: the construction takes r0 <= r1; otherwise swap the ends.
    RoundedCone c = cone;
    if (c.r0 > c.r1) c = RoundedCone(cone.x1, cone.r1, cone.x0, cone.r0);
    vec3 d = c.x1 - c.x0;
    vec3 d0 = orthographic ? -forward : eye - c.x0;
    vec3 d1 = orthographic ? -forward : eye - c.x1;
    float D0 = orthographic ? 1.0 : length(d0), D1 = orthographic ? 1.0 : length(d1);
    vec3 uu = cross(d, d0);  // Eq. 1
    float lu = length(uu);
    if (!(lu > 1e-6 * length(d) * D0)) {
        degenerate = true;
        return false;
    }
    // Only the part of the rounding error out of the plane perpendicular to d0 matters: removed.
    vec3 n0 = normalize(d0);
    vec3 u = normalize(uu / lu - n0 * dot(uu / lu, n0));
    vec3 v0 = normalize(cross(u, d0)), v1 = normalize(cross(u, d1));
    float rp0, rp1;
    if (!tcTangentRadius(c.x0, c.r0, eye, orthographic, rp0) || !tcTangentRadius(c.x1, c.r1, eye, orthographic, rp1))
        return false;
    vec3 p[4] = vec3[4](c.x0 + rp0 * v0, c.x0 - rp0 * v0, c.x1 + rp1 * v1, c.x1 - rp1 * v1);  // Eq. 4
    float sm = max(rp0 / D0, rp1 / D1);                                                       // Eq. 2, 5
    float rpp0 = D0 * sm, rpp1 = D1 * sm;
    vec3 w = normalize(cross(u, forward));  // Eq. 6
    float alpha[4];
    for (int i = 0; i < 4; ++i) alpha[i] = orthographic ? dot(p[i] - eye, w) : dot(normalize(p[i] - eye), w);  // Eq. 7
    vec3 ps = alpha[0] <= alpha[2] ? p[0] : p[2];  // Eq. 8
    float rs = alpha[0] <= alpha[2] ? rpp0 : rpp1;
    vec3 pe = alpha[1] <= alpha[3] ? p[3] : p[1];  // Eq. 9
    float re = alpha[1] <= alpha[3] ? rpp1 : rpp0;
    vec3 corners[4] = vec3[4](ps - rs * u, ps + rs * u, pe - re * u, pe + re * u);  // Eq. 10
    float referenceW = max((viewProj * vec4(c.x0, 1.0)).w, (viewProj * vec4(c.x1, 1.0)).w);
    for (int k = 0; k < 4; ++k)
        if (!tcProject(viewProj, corners[k], referenceW, q[k])) return false;
    return true;
}

// Every edge of q (strip order; polygon order 0,1,3,2) moved outward by pad.
void tcPadQuad(inout vec2 q[4], float pad) {
    const int order[4] = int[4](0, 1, 3, 2);
    vec2 poly[4];
    for (int i = 0; i < 4; ++i) poly[i] = q[order[i]];
    float area = 0.0;
    for (int i = 0; i < 4; ++i) {
        vec2 a = poly[i], b = poly[(i + 1) % 4];
        area += a.x * b.y - a.y * b.x;
    }
    float orient = area < 0.0 ? -1.0 : 1.0;
    vec2 normal[4];
    for (int i = 0; i < 4; ++i) {
        vec2 e = poly[(i + 1) % 4] - poly[i];
        float le = length(e);
        normal[i] = le > 0.0 ? orient * vec2(e.y, -e.x) / le : vec2(0.0);
    }
    for (int i = 0; i < 4; ++i) {
        vec2 na = normal[(i + 3) % 4], nb = normal[i];
        if (na == vec2(0.0)) na = nb;
        if (nb == vec2(0.0)) nb = na;
        q[order[i]] = poly[i] + pad * (na + nb) / max(1.0 + dot(na, nb), 0.1);
    }
}

// viewProj: world -> clip; eye, forward: Camera::eye, Camera::forward(); orthographic:
// Camera::projection == Orthographic.
Billboard computeBillboard(RoundedCone c, mat4 viewProj, vec3 eye, bool orthographic, vec3 forward) {
    float d0 = dot(c.x0 - eye, forward), d1 = dot(c.x1 - eye, forward);
    if (max(d0 + c.r0, d1 + c.r1) <= 0.0) {
        Billboard bb;
        for (int k = 0; k < 4; ++k) bb.ndc[k] = vec2(-2.0);
        bb.fullscreen = false;
        bb.culled = true;
        return bb;
    }

    float rmax = max(c.r0, c.r1);
    if (!orthographic) {
        if (sdRoundedCone(eye, c) <= 1e-4 * rmax) return tcBillboardFullscreen();
        if (min(d0 - c.r0, d1 - c.r1) <= 1e-6 * rmax) return tcBillboardFullscreen();
    }

    vec2 q[4];
    bool ok;
#ifdef BILLBOARD_RECTANGLE
    ok = tcRectangleQuad(c, viewProj, eye, orthographic, forward, q);
#else
    bool degenerate;
    ok = tcGross2020Quad(c, viewProj, eye, orthographic, forward, q, degenerate);
    if (degenerate) ok = tcRectangleQuad(c, viewProj, eye, orthographic, forward, q);
#endif
    if (!ok) return tcBillboardFullscreen();

    vec2 lo = min(min(q[0], q[1]), min(q[2], q[3])), hi = max(max(q[0], q[1]), max(q[2], q[3]));
    vec2 size = hi - lo;
    if (!(size.x < 1e30 && size.y < 1e30)) return tcBillboardFullscreen();
    tcPadQuad(q, 1e-5 * max(size.x, size.y) + 1e-6);
    Billboard bb;
    bb.ndc = q;
    bb.fullscreen = false;
    bb.culled = false;
    return bb;
}

// The corners alone (culled billboards are a zero-area quad, full-screen ones the screen), in the
// argument order rounded_cone_gbuffer.vert uses.
void computeBillboard(RoundedCone c, mat4 viewProj, vec3 eye, vec3 forward, bool orthographic,
                      out vec2 corners[4]) {
    Billboard bb = computeBillboard(c, viewProj, eye, orthographic, forward);
    corners = bb.ndc;
}

// The cone a segment's billboard must cover: its rounded cone, grown by the halo ring when the
// program has HALO (style.halo; transparent_fragment.glsl draws the ring).
RoundedCone billboardCone(vec4 a, vec4 b) {
#ifdef HALO
    const float scale = 1.0 + HALO_WIDTH;
#else
    const float scale = 1.0;
#endif
    return RoundedCone(a.xyz, a.w * scale, b.xyz, b.w * scale);
}

#endif  // TC_BILLBOARD_GLSL
