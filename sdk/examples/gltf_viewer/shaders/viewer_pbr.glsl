// glTF metallic-roughness shading (glTF 2.0 spec appendix B: GGX / Smith-Schlick / Schlick
// Fresnel, Lambert diffuse), an analytic sky-gradient environment for background and ambient,
// and Toksvig's roughness widening from a pre-filtered normal map: shared by the forward pass
// and the deferred fovea_shade(), so both paths shade alike.
#ifndef VIEWER_PBR_GLSL
#define VIEWER_PBR_GLSL

const float kViewerPi = 3.14159265358979;

// The environment seen along unit direction d (sky above, ground below, a soft horizon band).
vec3 viewer_environment(vec3 d) {
    float y = d.y;
    vec3 up = mix(viewer_scene.horizon.rgb, viewer_scene.sky.rgb, smoothstep(0.0, 0.6, y));
    vec3 down = mix(viewer_scene.horizon.rgb, viewer_scene.ground.rgb, smoothstep(0.0, 0.25, -y));
    return (y >= 0.0 ? up : down) * viewer_scene.sky.w;
}

struct ViewerSurface {
    vec3 position;
    vec3 normal;  // unit, shading normal
    vec3 base_color;
    float metallic;
    float roughness;  // perceptual
    float occlusion;
    vec3 emissive;
    float f0;
};

vec3 viewer_brdf(ViewerSurface s, vec3 n, vec3 v, vec3 l) {
    vec3 h = normalize(l + v);
    float nl = max(dot(n, l), 0.0), nv = max(dot(n, v), 1e-4), nh = max(dot(n, h), 0.0);
    float vh = clamp(dot(v, h), 0.0, 1.0);  // rounding can pass 1: pow(negative) is NaN
    float a = max(s.roughness * s.roughness, 1e-3), a2 = a * a;
    float dd = nh * nh * (a2 - 1.0) + 1.0;
    float d = a2 / (kViewerPi * dd * dd);
    float k = a * 0.5;
    float g = nv / (nv * (1.0 - k) + k) * nl / (nl * (1.0 - k) + k);
    vec3 f0 = mix(vec3(s.f0), s.base_color, s.metallic);
    vec3 f = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);
    vec3 diffuse = (1.0 - f) * (1.0 - s.metallic) * s.base_color / kViewerPi;
    return (diffuse + f * d * g / max(4.0 * nv * nl, 1e-4)) * nl;
}

vec3 viewer_shade_surface(ViewerSurface s, vec3 eye) {
    vec3 v = normalize(eye - s.position);
    vec3 n = s.normal;
    if (dot(n, v) < 0.0) n = -n;  // seen from behind (double-sided or interpolation)
    vec3 c = vec3(0.0);
    for (int i = 0; i < viewer_scene.counts.x; ++i) {
        ViewerLight light = viewer_scene.lights[i];
        vec3 l;
        vec3 radiance = light.color.rgb;
        if (light.position.w > 0.5) {
            vec3 to = light.position.xyz - s.position;
            float d2 = max(dot(to, to), 1e-6);
            l = to * inversesqrt(d2);
            radiance /= d2;
        } else {
            l = -normalize(light.position.xyz);
        }
        c += viewer_brdf(s, n, v, l) * radiance;
    }
    // Ambient: diffuse from the environment above the normal, specular from the reflection
    // direction (the sky is smooth, so no pre-filtered map is needed).
    vec3 f0 = mix(vec3(s.f0), s.base_color, s.metallic);
    vec3 amb = viewer_environment(n) * s.base_color * (1.0 - s.metallic);
    vec3 spec = viewer_environment(reflect(-v, n)) * f0 * (1.0 - 0.6 * s.roughness);
    c += (amb + spec) * s.occlusion * 0.5;
    return c + s.emissive;
}

// Toksvig 2005: a normal map averaged over a footprint shortens; its length |n_avg| widens the
// lobe: roughness^2 grows by (1 - |n|) / |n|. Keeps speculars of coarse samples from aliasing.
float viewer_toksvig_roughness(float roughness, float avg_normal_length) {
    float len = clamp(avg_normal_length, 1e-3, 1.0);
    float a2 = roughness * roughness * roughness * roughness;  // alpha^2, alpha = r^2
    a2 += (1.0 - len) / len;
    return sqrt(sqrt(min(a2, 1.0)));
}

#endif
