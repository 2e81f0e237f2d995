#version 450
// Meng 2018 pass II: every screen pixel reads the LP buffer at its kernel log-polar coordinate
// (bilinear, v wrapping across the ±π seam) with 4 rotated-grid sub-samples as anti-aliasing.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "kfr_map.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D lp_in;

vec4 lp_bilinear(vec2 lp) {
    ivec2 size = ivec2(kfr.lp_size);
    vec2 f = lp - 0.5;
    vec2 b = floor(f);
    vec2 w = f - b;
    int u0 = clamp(int(b.x), 0, size.x - 1);
    int u1 = clamp(int(b.x) + 1, 0, size.x - 1);
    int v0 = ((int(b.y) % size.y) + size.y) % size.y;
    int v1 = (v0 + 1) % size.y;
    vec4 a = mix(imageLoad(lp_in, ivec2(u0, v0)), imageLoad(lp_in, ivec2(u1, v0)), w.x);
    vec4 c = mix(imageLoad(lp_in, ivec2(u0, v1)), imageLoad(lp_in, ivec2(u1, v1)), w.x);
    return mix(a, c, w.y);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ivec2(kfr.screen)))) return;
    const vec2 kOffsets[4] = vec2[](vec2(0.125, 0.375), vec2(0.375, -0.125),
                                    vec2(-0.125, -0.375), vec2(-0.375, 0.125));
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 4; ++i) sum += lp_bilinear(kfr_forward(vec2(p) + 0.5 + kOffsets[i]));
    vec3 c = sum.a > 0.0 ? sum.rgb / sum.a : vec3(0.0);
    float fp = kfr_texel_footprint(kfr_forward(vec2(p) + 0.5).x);
    imageStore(fovea_out_color, p, vec4(c, 1.0));
    imageStore(fovea_out_rate, p, vec4(clamp(log2(max(fp, 1.0)) * 0.5, 0.0, 1.0)));
}
