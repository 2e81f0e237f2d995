// The demo scene's geometry (tools/demo, DESIGN.md §6): a sine-sum terrain, a 6 x 4 grid of
// parametric objects (spheres, boxes, cylinders, ellipsoids) standing on it, and screen-facing
// test targets (zone plate, grating). Rasterized by demo_*.vert/.frag (tools/demo/scene.cpp);
// materials are shaded by demo_shading.glsl. Material ids: 0 sky, 1 terrain, 2-5 object
// materials, 10 zone plate, 11 grating.
#ifndef FOVEA_DEMO_SCENE_GLSL
#define FOVEA_DEMO_SCENE_GLSL

const int kDemoScene = 0;
const int kZonePlateScene = 1;
const int kGratingScene = 2;
// The object grid. tools/demo/scene.cpp draws 36 * kGridX * kGridZ proxy vertices
// (kObjectVertices): change both together.
const int kGridX = 6;
const int kGridZ = 4;

float demo_terrain_height(vec2 xz) {
    return 1.4 * sin(0.13 * xz.x + 0.4) * cos(0.11 * xz.y) + 0.55 * sin(0.37 * xz.x + 0.29 * xz.y) +
           0.22 * sin(1.07 * xz.x + 0.3) * sin(0.83 * xz.y + 1.1) - 1.0;
}

// The height field's exact normal (its analytic gradient: half the sines of finite differences).
vec3 demo_terrain_normal(vec2 xz) {
    float a = 0.13 * xz.x + 0.4, b = 0.11 * xz.y, c = 0.37 * xz.x + 0.29 * xz.y;
    float d = 1.07 * xz.x + 0.3, e = 0.83 * xz.y + 1.1;
    float sa = sin(a), ca = cos(a), sb = sin(b), cb = cos(b), cc = cos(c);
    float sd = sin(d), cd = cos(d), se = sin(e), ce = cos(e);
    float dx = 1.4 * 0.13 * ca * cb + 0.55 * 0.37 * cc + 0.22 * 1.07 * cd * se;
    float dz = -1.4 * 0.11 * sa * sb + 0.55 * 0.29 * cc + 0.22 * 0.83 * sd * ce;
    return normalize(vec3(-dx, 1.0, -dz));
}

// Object i of the grid: centre, half size, shape (0 sphere, 1 box, 2 cylinder, 3 ellipsoid).
void demo_object(int i, out vec3 centre, out vec3 half_size, out int shape) {
    int gx = i % kGridX;
    int gz = i / kGridX;
    float x = -12.5 + 5.0 * float(gx);
    float z = -9.0 - 6.5 * float(gz);
    shape = (gx + gz) % 4;
    float s = 0.9 + 0.25 * float((gx * 7 + gz * 3) % 3);
    half_size = shape == 3 ? vec3(s * 1.3, s * 0.8, s) : vec3(s);
    centre = vec3(x, demo_terrain_height(vec2(x, z)) + half_size.y + 0.05, z);
}

// Ray/object intersection: distance along the unit ray and the normal; t < 0 when missed.
float demo_intersect_object(int shape, vec3 c, vec3 hs, vec3 ro, vec3 rd, out vec3 n) {
    n = vec3(0.0, 1.0, 0.0);
    vec3 o = ro - c;
    if (shape == 0 || shape == 3) {  // sphere / ellipsoid: scale to the unit sphere
        vec3 os = o / hs;
        vec3 ds = rd / hs;
        float a = dot(ds, ds), b = dot(os, ds), cc = dot(os, os) - 1.0;
        float disc = b * b - a * cc;
        if (disc < 0.0) return -1.0;
        float t = (-b - sqrt(disc)) / a;
        if (t <= 0.0) return -1.0;
        n = normalize((o + t * rd) / (hs * hs));
        return t;
    }
    if (shape == 1) {  // axis-aligned box
        vec3 inv = 1.0 / rd;
        vec3 t0 = (-hs - o) * inv, t1 = (hs - o) * inv;
        vec3 tmin = min(t0, t1), tmax = max(t0, t1);
        float tn = max(max(tmin.x, tmin.y), tmin.z);
        float tf = min(min(tmax.x, tmax.y), tmax.z);
        if (tn > tf || tn <= 0.0) return -1.0;
        if (tn == tmin.x) n = vec3(-sign(rd.x), 0.0, 0.0);
        else if (tn == tmin.y) n = vec3(0.0, -sign(rd.y), 0.0);
        else n = vec3(0.0, 0.0, -sign(rd.z));
        return tn;
    }
    // vertical capped cylinder, radius hs.x, half height hs.y
    float best = -1.0;
    float a = dot(rd.xz, rd.xz);
    if (a > 1e-8) {
        float b = dot(o.xz, rd.xz), cc = dot(o.xz, o.xz) - hs.x * hs.x;
        float disc = b * b - a * cc;
        if (disc >= 0.0) {
            float t = (-b - sqrt(disc)) / a;
            if (t > 0.0 && abs(o.y + t * rd.y) <= hs.y) {
                best = t;
                n = normalize(vec3(o.x + t * rd.x, 0.0, o.z + t * rd.z));
            }
        }
    }
    if (abs(rd.y) > 1e-8) {
        float cap = rd.y < 0.0 ? hs.y : -hs.y;
        float t = (cap - o.y) / rd.y;
        vec2 q = o.xz + t * rd.xz;
        if (t > 0.0 && dot(q, q) <= hs.x * hs.x && (best < 0.0 || t < best)) {
            best = t;
            n = vec3(0.0, sign(cap), 0.0);
        }
    }
    return best;
}

#endif
