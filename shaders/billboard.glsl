// View-aligned billboard of one rounded cone (Groß & Gumhold 2020, Sect. 5.1): the GPU twin of
// core/billboard.cpp (same math, names and edge cases; keep them in lock-step). GLSL 4.50 chunk,
// #include'd after rounded_cone.glsl (for RoundedCone and sdRoundedCone).
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

// Squares x_i +- r'_i a_i +- r'_i b_i around the eye's tangent-cone cross-sections
// (r'_i = |d_i| r_i / sqrt(|d_i|^2 - r_i^2); orthographic: r'_i = r_i), projected; the rectangle
// aligned with the projected axis around them. viewProj: world -> clip; eye, forward:
// Camera::eye, Camera::forward(); orthographic: Camera::projection == Orthographic.
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

    vec3 ba = c.x1 - c.x0;
    vec2 pts[8];
    vec2 centre[2];
    for (int i = 0; i < 2; ++i) {
        vec3 xi = i == 0 ? c.x0 : c.x1;
        float ri = i == 0 ? c.r0 : c.r1;
        vec3 di = eye - xi;
        float D = length(di);
        vec3 v = orthographic ? -forward : di / D;
        float rp = ri;
        if (!orthographic) {
            float k = (D - ri) * (D + ri);
            if (!(k > 1e-8 * D * D)) return tcBillboardFullscreen();
            rp = D * ri / sqrt(k);
        }
        vec3 a = ba - v * dot(ba, v);
        float la = length(a);
        a = la > 1e-6 * length(ba) && la > 0.0 ? a / la : tcAnyPerpendicular(v);
        vec3 b = cross(v, a);
        vec4 cc = viewProj * vec4(xi, 1.0);
        centre[i] = cc.xy / cc.w;
        for (int k = 0; k < 4; ++k) {
            float sa = (k & 1) != 0 ? 1.0 : -1.0, sb = (k & 2) != 0 ? 1.0 : -1.0;
            vec4 p = viewProj * vec4(xi + (sa * rp) * a + (sb * rp) * b, 1.0);
            if (!(p.w > 1e-6 * cc.w)) return tcBillboardFullscreen();
            pts[4 * i + k] = p.xy / p.w;
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
    if (!(hiE - loE < 1e30 && hiF - loF < 1e30)) return tcBillboardFullscreen();
    float padE = 1e-5 * (hiE - loE) + 1e-6, padF = 1e-5 * (hiF - loF) + 1e-6;
    loE -= padE; hiE += padE; loF -= padF; hiF += padF;
    Billboard bb;
    bb.ndc[0] = loE * e + loF * f;
    bb.ndc[1] = hiE * e + loF * f;
    bb.ndc[2] = loE * e + hiF * f;
    bb.ndc[3] = hiE * e + hiF * f;
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
