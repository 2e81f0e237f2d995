// TAA pass 3: variance-sampled resolve (Patney §4.2–4.3). Clamp box μ ± γσ from the moment chain
// at LOD = 4·S_t (manual trilinear: bit-comparable with the CPU model), grown to contain the
// current sample; history fetched with a 16-tap Catmull-Rom and clipped toward the box centre in
// YCoCg; saccade-aware α from the accumulated S in the history's alpha; disocclusion from depth
// and from motion leaving the screen. Mirrors taa_resolve() in sdk/src/vk/post/taa_model.cpp.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, r32f) uniform readonly image2D depth_in;
layout(set = 0, binding = 2, rg16f) uniform readonly image2D motion_in;
layout(set = 0, binding = 3, r16f) uniform readonly image2D rate_in;
layout(set = 0, binding = 4) uniform sampler2D m1_tex;  // all mips; texelFetch only
layout(set = 0, binding = 5) uniform sampler2D m2_tex;
layout(set = 0, binding = 6, TAA_FORMAT) uniform readonly image2D hist_in;
layout(set = 0, binding = 7, r32f) uniform readonly image2D hist_depth_in;
layout(set = 0, binding = 8, TAA_FORMAT) uniform writeonly image2D hist_out;
layout(set = 0, binding = 9, r32f) uniform writeonly image2D hist_depth_out;
layout(set = 0, binding = 10, rgba16f) uniform writeonly image2D color_out;

layout(push_constant) uniform Push {
    float alpha;
    float alpha_max;
    float beta;
    float gamma;
    float depth_tolerance;
    int levels;
    uint flags;  // bit 0: history valid, bit 1: saccade term on
} pc;

#include "taa_common.glsl"

// Bilinear texelFetch of one level at full-resolution pixel centre px (clamp-to-edge).
vec3 fetch_level(sampler2D t, vec2 px, vec2 full, int level) {
    ivec2 size = textureSize(t, level);
    vec2 f = px / full * vec2(size) - 0.5;
    vec2 b = floor(f);
    vec2 a = f - b;
    ivec2 i0 = ivec2(b);
    ivec2 hi = size - 1;
    vec3 s00 = texelFetch(t, clamp(i0, ivec2(0), hi), level).xyz;
    vec3 s10 = texelFetch(t, clamp(i0 + ivec2(1, 0), ivec2(0), hi), level).xyz;
    vec3 s01 = texelFetch(t, clamp(i0 + ivec2(0, 1), ivec2(0), hi), level).xyz;
    vec3 s11 = texelFetch(t, clamp(i0 + ivec2(1, 1), ivec2(0), hi), level).xyz;
    vec3 x0 = s00 * (1.0 - a.x) + s10 * a.x;
    vec3 x1 = s01 * (1.0 - a.x) + s11 * a.x;
    return x0 * (1.0 - a.y) + x1 * a.y;
}

// The level index stays uniform across invocations (lavapipe mis-fetches with a per-invocation
// texelFetch level); the weights select the two levels trilinear filtering blends.
vec3 fetch_trilinear(sampler2D t, vec2 px, vec2 full, float lod) {
    lod = clamp(lod, 0.0, float(pc.levels - 1));
    int l0 = int(floor(lod));
    float f = lod - float(l0);
    vec3 a = vec3(0.0);
    vec3 b = vec3(0.0);
    int l1 = min(l0 + 1, pc.levels - 1);
    for (int l = 0; l < pc.levels; ++l) {
        if (l != l0 && l != l1) continue;
        vec3 v = fetch_level(t, px, full, l);
        if (l == l0) a = v;
        if (l == l1) b = v;
    }
    return f > 0.0 ? a + (b - a) * f : a;
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(color_in);
    if (any(greaterThanEqual(p, size))) return;
    vec2 full = vec2(size);

    vec3 cur_t = taa_tonemap(imageLoad(color_in, p).rgb);
    vec3 cur_q = taa_rgb_to_ycocg(cur_t);
    float s_raw = imageLoad(rate_in, p).x;
    float s_cur = (isnan(s_raw) || isinf(s_raw)) ? 1.0 : clamp(s_raw, 0.0, 1.0);
    float d_raw = imageLoad(depth_in, p).x;
    float d_cur = (isnan(d_raw) || isinf(d_raw)) ? 0.0 : d_raw;

    vec3 blended_q = cur_q;
    float blended_s = s_cur;
    vec2 px = vec2(p) + 0.5;
    vec2 m = imageLoad(motion_in, p).xy;
    if (any(isnan(m)) || any(isinf(m))) m = vec2(-1e9);
    vec2 q = px - m;  // motion = current - previous
    bool on_screen = q.x >= 0.0 && q.y >= 0.0 && q.x < full.x && q.y < full.y;
    bool have_history = (pc.flags & 1u) != 0u;
    bool occluded = !on_screen;
    if (have_history && on_screen) {
        float d_prev = imageLoad(hist_depth_in, ivec2(q)).x;
        occluded = abs(d_prev - d_cur) > pc.depth_tolerance * max(abs(d_cur), 1e-6);
    }
    if (have_history && !occluded) {
        vec2 f = q - 0.5;
        vec2 b = floor(f);
        vec4 wx = taa_catmull_rom(f.x - b.x);
        vec4 wy = taa_catmull_rom(f.y - b.y);
        ivec2 base = ivec2(b) - 1;
        vec4 acc = vec4(0.0);
        for (int j = 0; j < 4; ++j) {
            for (int i = 0; i < 4; ++i) {
                ivec2 t = clamp(base + ivec2(i, j), ivec2(0), size - 1);
                acc += wx[i] * wy[j] * imageLoad(hist_in, t);
            }
        }
        vec3 hist_t = max(acc.rgb, vec3(0.0));
        float s_prev = clamp(acc.a, 0.0, 1.0);

        float lod = 4.0 * s_cur;
        vec3 m1 = fetch_trilinear(m1_tex, px, full, lod);
        vec3 m2 = fetch_trilinear(m2_tex, px, full, lod);
        vec3 sigma = sqrt(max(m2 - m1 * m1, vec3(0.0)));  // never a negative variance
        vec3 lo = min(m1 - pc.gamma * sigma, cur_q);
        vec3 hi = max(m1 + pc.gamma * sigma, cur_q);
        vec3 hist_q = taa_clip(taa_rgb_to_ycocg(hist_t), 0.5 * (lo + hi), 0.5 * (hi - lo));
        float a = taa_saccade_alpha(s_prev, s_cur, pc.alpha, pc.alpha_max, pc.beta,
                                    (pc.flags & 2u) != 0u);
        blended_q = mix(hist_q, cur_q, a);
        blended_s = s_prev + (s_cur - s_prev) * a;
    }
    vec3 t = clamp(taa_ycocg_to_rgb(blended_q), vec3(0.0), vec3(kTaaMaxTonemapped));
    imageStore(hist_out, p, vec4(t, blended_s));
    imageStore(hist_depth_out, p, vec4(d_cur));
    // Read back what the history stores (half or float) so output and history agree.
    imageStore(color_out, p, vec4(taa_tonemap_inverse(t), 1.0));
}
