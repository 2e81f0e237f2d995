// The demo host's shading function (the contract in sdk/include/fovea/vk/foveator.hpp): deliberately
// expensive, in the spirit of Guenter's test scene — 24 coloured point lights plus a sun with GGX
// specular, an analytic environment map (sky gradient, sun, fbm clouds) for the background and
// reflections, and procedural textures with high-frequency detail (fbm value noise, filtered
// checkers, stripes). Everything is pre-filtered over the footprint fp.world_size, so coarse
// shades stay alias-free. Test targets: zone plate (material 10) and grating (11) on the plane
// z = -1 in front of a camera at the origin, with Gaussian pre-filtering of their sinusoids.
//   host[0].x: zone plate k (phase = pi k r^2, r in plane units); host[0].y: grating frequency
//   (cycles per plane unit); host[0].z: plane units per pixel (for the pre-filter width).

const int kLights = 24;
const float kPi = 3.14159265358979;

float demo_hash(vec3 p) {
    p = fract(p * 0.3183099 + vec3(0.1, 0.2, 0.3));
    p *= 17.0;
    return fract(p.x * p.y * p.z * (p.x + p.y + p.z));
}

float demo_value_noise(vec3 x) {
    vec3 i = floor(x);
    vec3 f = fract(x);
    f = f * f * (3.0 - 2.0 * f);
    return mix(mix(mix(demo_hash(i + vec3(0, 0, 0)), demo_hash(i + vec3(1, 0, 0)), f.x),
                   mix(demo_hash(i + vec3(0, 1, 0)), demo_hash(i + vec3(1, 1, 0)), f.x), f.y),
               mix(mix(demo_hash(i + vec3(0, 0, 1)), demo_hash(i + vec3(1, 0, 1)), f.x),
                   mix(demo_hash(i + vec3(0, 1, 1)), demo_hash(i + vec3(1, 1, 1)), f.x), f.y),
               f.z);
}

// fbm with octaves above the footprint's Nyquist faded out (pre-filtering by band limiting).
float demo_fbm(vec3 p, float base_freq, int octaves, float footprint) {
    float sum = 0.0, amp = 0.5, freq = base_freq, norm = 0.0;
    for (int o = 0; o < octaves; ++o) {
        float w = clamp(2.0 - 2.0 * freq * footprint, 0.0, 1.0);  // 1 below 0.5 cycles/footprint
        sum += amp * w * (demo_value_noise(p * freq) - 0.5);
        norm += amp;
        amp *= 0.55;
        freq *= 2.03;
    }
    return 0.5 + sum / max(norm, 1e-4);
}

// Box-filtered checker (analytic integral of the square wave over the footprint).
float demo_checker(vec2 p, float w) {
    vec2 fw = vec2(max(w, 1e-4));
    vec2 i = 2.0 * (abs(fract((p - 0.5 * fw) * 0.5) - 0.5) - abs(fract((p + 0.5 * fw) * 0.5) - 0.5)) / fw;
    return 0.5 - 0.5 * i.x * i.y;
}

vec3 demo_sky(vec3 d, float footprint_rad) {
    vec3 sun = normalize(vec3(0.4, 0.55, -0.7));
    float h = clamp(d.y, -1.0, 1.0);
    vec3 col = mix(vec3(0.75, 0.8, 0.85), vec3(0.22, 0.42, 0.8), clamp(h * 1.5, 0.0, 1.0));
    if (h < 0.0) col = mix(vec3(0.75, 0.8, 0.85), vec3(0.3, 0.28, 0.25), clamp(-h * 4.0, 0.0, 1.0));
    float s = max(dot(d, sun), 0.0);
    col += vec3(1.0, 0.85, 0.6) * (pow(s, 600.0) * 6.0 + pow(s, 12.0) * 0.25);
    if (h > 0.02) {
        vec3 cp = d / h * 3.0;  // cloud layer
        float c = demo_fbm(vec3(cp.x, 0.0, cp.z), 1.3, 6, footprint_rad * 3.0 / h);
        col = mix(col, vec3(0.95), smoothstep(0.5, 0.75, c) * clamp(h * 4.0, 0.0, 1.0) * 0.8);
    }
    return col;
}

vec3 demo_light_pos(int i, float time) {
    float a = 6.2831853 * float(i) / float(kLights) + 0.05 * time;
    float r = 6.0 + 6.0 * float(i % 3);
    return vec3(r * cos(a), 2.5 + float(i % 4), -18.0 + r * 0.8 * sin(a));
}

vec3 demo_light_color(int i) {
    return vec3(0.5 + 0.5 * cos(float(i) * 1.7), 0.5 + 0.5 * cos(float(i) * 1.7 + 2.1),
                0.5 + 0.5 * cos(float(i) * 1.7 + 4.2)) * 6.0;
}

// GGX specular + Lambert for one light.
vec3 demo_brdf(vec3 n, vec3 v, vec3 l, vec3 albedo, float rough, float metal) {
    vec3 h = normalize(v + l);
    float nl = max(dot(n, l), 0.0), nv = max(dot(n, v), 1e-3), nh = max(dot(n, h), 0.0);
    float a = rough * rough, a2 = a * a;
    float d = a2 / (kPi * pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
    float k = a * 0.5;
    float g = nv / (nv * (1.0 - k) + k) * nl / (nl * (1.0 - k) + k);
    vec3 f0 = mix(vec3(0.04), albedo, metal);
    // Clamped on both sides: where v and l are nearly parallel (distant terrain, lit from near
    // the camera) rounding puts dot(h, v) above 1, and pow() of a negative base is NaN.
    vec3 f = f0 + (1.0 - f0) * pow(clamp(1.0 - dot(h, v), 0.0, 1.0), 5.0);
    vec3 spec = d * g * f / max(4.0 * nv * nl, 1e-3);
    return ((1.0 - metal) * albedo / kPi * (1.0 - f) + spec) * nl;
}

vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) {
    int id = int(g.material.x + 0.5);
    if (g.background) return demo_sky(normalize(g.normal), fp.size_px * fovea_frame.camera_pos.w);
    if (id == 10 || id == 11) {
        // Gaussian pre-filter of a sinusoid of local frequency f: amplitude exp(-2 pi^2 s^2 f^2)
        // with s = footprint / 3 (keeps what the coarse grid can carry, removes what it aliases).
        float unit = fovea_frame.host[0].z * fp.size_px / 3.0;
        vec2 q = g.position.xy;
        float phase, f;
        if (id == 10) {
            float r2 = dot(q, q);
            phase = kPi * fovea_frame.host[0].x * r2;
            f = fovea_frame.host[0].x * sqrt(r2);  // d(phase)/dr / 2pi
        } else {
            phase = 2.0 * kPi * fovea_frame.host[0].y * q.x;
            f = fovea_frame.host[0].y;
        }
        float att = exp(-2.0 * kPi * kPi * unit * unit * f * f);
        return vec3(0.5 + 0.5 * att * cos(phase));
    }
    vec3 p = g.position;
    vec3 n = normalize(g.normal);
    vec3 v = normalize(fovea_frame.camera_pos.xyz - p);
    float w = max(fp.world_size, 1e-4);
    vec3 albedo = g.albedo;
    float rough = g.material.y;
    float metal = g.material.z;
    if (id == 1) {  // terrain: grass/rock/soil fbm with fine detail
        float fine = demo_fbm(p * vec3(1.0, 2.0, 1.0), 3.0, 7, w);
        float coarse = demo_fbm(p, 0.25, 4, w);
        albedo = mix(vec3(0.25, 0.33, 0.12), vec3(0.45, 0.4, 0.33), smoothstep(0.4, 0.6, coarse));
        albedo *= 0.6 + 0.8 * fine;
        albedo = mix(albedo, vec3(0.5), smoothstep(0.55, 0.8, 1.0 - n.y) * 0.7);
    } else if (id == 2) {  // sphere: marble
        float m = demo_fbm(p * 2.0, 1.0, 6, w * 2.0);
        albedo *= 0.55 + 0.45 * sin(8.0 * p.y + 10.0 * m);
    } else if (id == 3) {  // box: fine checker
        vec2 uv = abs(n.y) > 0.5 ? p.xz : (abs(n.x) > 0.5 ? p.zy : p.xy);
        albedo *= 0.35 + 0.65 * demo_checker(uv * 8.0, w * 8.0);
    } else if (id == 4) {  // cylinder: brushed stripes
        float s = demo_fbm(vec3(p.x * 40.0, p.y * 0.5, p.z * 40.0), 1.0, 5, w * 40.0);
        albedo *= 0.6 + 0.4 * s;
        metal = 1.0;
    } else {  // ellipsoid: noise bumps in albedo
        albedo *= 0.5 + demo_fbm(p * 5.0, 1.0, 6, w * 5.0);
    }
    vec3 col = vec3(0.0);
    for (int i = 0; i < kLights; ++i) {
        vec3 lp = demo_light_pos(i, fovea_frame.time.x);
        vec3 l = lp - p;
        float d2 = dot(l, l);
        col += demo_brdf(n, v, l * inversesqrt(d2), albedo, rough, metal) * demo_light_color(i) / d2;
    }
    vec3 sun = normalize(vec3(0.4, 0.55, -0.7));
    col += demo_brdf(n, v, sun, albedo, rough, metal) * vec3(2.2, 2.0, 1.8);
    vec3 refl = reflect(-v, n);
    vec3 f0 = mix(vec3(0.04), albedo, metal);
    col += demo_sky(refl, rough + fp.size_px * fovea_frame.camera_pos.w) * f0 * (1.0 - rough) * 0.6;
    col += albedo * demo_sky(n, 1.0) * 0.15;  // ambient from the environment
    return col;
}

// The environment alone, for background-only tiles (method cps skips fovea_shade there): the
// same as fovea_shade's background branch, so skipping changes no pixel.
vec3 fovea_background(FoveaGSample g, FoveaFootprint fp) {
    return demo_sky(normalize(g.normal), fp.size_px * fovea_frame.camera_pos.w);
}
