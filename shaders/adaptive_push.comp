#version 450
// Push: fill each texel's missing weight from the bilinearly upsampled coarser level,
// c = w·c_fine + (1 - w)·c_coarse. At level 0 the result is the method's output colour.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D coarse;
layout(set = 1, binding = 1, rgba16f) uniform image2D fine;
// The last push (level 0) writes the method's output instead of the pyramid (no branch on a
// uniform: llvmpipe would run both stores).
layout(constant_id = 0) const bool FINAL = false;

vec3 coarse_bilinear(vec2 pos) {
    ivec2 cs = imageSize(coarse) - 1;
    vec2 f = pos - 0.5;
    ivec2 b = ivec2(floor(f));
    vec2 w = f - vec2(b);
    vec3 a = mix(imageLoad(coarse, clamp(b, ivec2(0), cs)).rgb,
                 imageLoad(coarse, clamp(b + ivec2(1, 0), ivec2(0), cs)).rgb, w.x);
    vec3 c = mix(imageLoad(coarse, clamp(b + ivec2(0, 1), ivec2(0), cs)).rgb,
                 imageLoad(coarse, clamp(b + ivec2(1, 1), ivec2(0), cs)).rgb, w.x);
    return mix(a, c, w.y);
}

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(fine)))) return;
    vec4 f = imageLoad(fine, t);
    vec3 c = f.rgb * f.a + (1.0 - f.a) * coarse_bilinear((vec2(t) + 0.5) * 0.5);
    if (FINAL) imageStore(fovea_out_color, t, vec4(c, 1.0));
    else imageStore(fine, t, vec4(c, 1.0));
}
