// Two-sided Blinn-Phong: the GPU twin of core/shading.h (keep them in lock-step). GLSL 4.50
// chunk, #include'd.
#ifndef TC_SHADING_GLSL
#define TC_SHADING_GLSL

// base: linear RGB; n: outward unit normal; dir: unit ray direction (eye -> point); lightDir:
// unit world direction toward the light (tc::lightDirectionWorld on the CPU, passed as a
// uniform). Returns linear RGB, not premultiplied.
vec3 shadeBlinnPhong(vec3 base, vec3 n, vec3 dir, vec3 lightDir, float ambient, float diffuse,
                     float specular, float shininess) {
    vec3 v = -dir;
    vec3 nf = dot(n, v) >= 0.0 ? n : -n;
    float ndl = dot(nf, lightDir);
    vec3 color = base * (ambient + diffuse * max(ndl, 0.0));
    // ndl > 0 and dot(nf, v) >= 0 imply lightDir != -v, so the half vector is defined.
    if (ndl > 0.0) {
        vec3 h = normalize(lightDir + v);
        color += vec3(specular * pow(max(dot(nf, h), 0.0), shininess));
    }
    return color;
}

#endif  // TC_SHADING_GLSL
