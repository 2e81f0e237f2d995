#version 450
// Meng 2018 pass II: every screen pixel reads the LP buffer at its kernel log-polar coordinate
// (bilinear, v wrapping across the ±π seam); anti-aliasing comes from the LP-space prefilter.
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
    vec2 jx, jy;
    float radial, angular;
    vec2 lp = kfr_forward_jacobian(vec2(p) + 0.5, jx, jy, radial, angular);
    // One bilinear tap: the minified region near the gaze was prefiltered along v in LP space
    // (kfr_blur.comp), and where LP texels are larger than a pixel bilinear is already smooth.
    vec4 c = lp_bilinear(lp);
    imageStore(fovea_out_color, p, vec4(c.a > 0.0 ? c.rgb / c.a : vec3(0.0), 1.0));
    float s_t = clamp(log2(max(max(radial, angular), 1.0)) * 0.5, 0.0, 1.0);
    imageStore(fovea_out_rate, p, vec4(s_t));
}
