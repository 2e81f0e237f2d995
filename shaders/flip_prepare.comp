#version 450
// LDR-FLIP step 1: one image's texels -> YCxCz (w: 1 where the pixel counts, 0 where a
// back-projection left the previous frame). Kinds: flip_common.glsl.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;

#include "flip_common.glsl"
#define FLIP_COLOUR_BINDING 4
#include "flip_colour.glsl"

layout(set = 0, binding = 0) uniform sampler2D input_a;  // the image (kFlipBackProject: previous)
layout(set = 0, binding = 1) uniform sampler2D input_b;  // kFlipBackProject: the current frame
layout(std430, set = 0, binding = 2) readonly buffer Motion {
    vec2 motion[];  // kFlipBackProject: current - previous position of each pixel centre, pixels
};
// Written through a storage texel buffer: on llvmpipe one 16-byte store per lane, not four
// bounds-checked scalar stores.
layout(set = 0, binding = 3, rgba32f) uniform writeonly imageBuffer opponent;
// The linear value of each 8-bit sRGB code (the CPU reference's, in double): a fetch instead of
// three pow()s where the input is 8-bit codes.
layout(set = 0, binding = 5) uniform samplerBuffer srgb_lut;

layout(push_constant) uniform Push { uvec2 size; };
// One pipeline per kind: llvmpipe runs both sides of every branch under a lane mask, so a kind
// chosen at run time would pay for the back-projection's four fetches and transforms always.
layout(constant_id = 0) const uint kind = kFlipSrgb;

vec3 linear_of_codes(vec3 code) {
    ivec3 i = ivec3(code);
    return vec3(texelFetch(srgb_lut, i.r).x, texelFetch(srgb_lut, i.g).x,
                texelFetch(srgb_lut, i.b).x);
}

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, size))) return;
    ivec2 ip = ivec2(p);
    vec3 srgb, lin;
    float valid = 1.0;
    if (kind == kFlipSrgb8) {
        lin = linear_of_codes(floor(texelFetch(input_a, ip, 0).rgb * 255.0 + 0.5));
    } else if (kind == kFlipDemoDisplay) {
        lin = linear_of_codes(flip_demo_code(texelFetch(input_a, ip, 0).rgb));
    } else if (kind == kFlipBackProject) {
        // As bench::temporal_difference: the pixel centre's previous position, bilinear between
        // texel centres, both neighbours inside; elsewhere the current pixel (no difference)
        // marked invalid.
        vec2 m = motion[p.y * size.x + p.x];
        vec2 q = vec2(p) - m;
        if (!any(isnan(m)) && !any(isinf(m)) && q.x >= 0.0 && q.y >= 0.0 &&
            q.x <= float(size.x - 1u) && q.y <= float(size.y - 1u)) {
            ivec2 q0 = ivec2(q);
            ivec2 q1 = min(q0 + 1, ivec2(size) - 1);
            vec2 f = q - vec2(q0);
            vec3 a = flip_demo_display(texelFetch(input_a, q0, 0).rgb);
            vec3 b = flip_demo_display(texelFetch(input_a, ivec2(q1.x, q0.y), 0).rgb);
            vec3 c = flip_demo_display(texelFetch(input_a, ivec2(q0.x, q1.y), 0).rgb);
            vec3 d = flip_demo_display(texelFetch(input_a, q1, 0).rgb);
            srgb = mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
        } else {
            srgb = flip_demo_display(texelFetch(input_b, ip, 0).rgb);
            valid = 0.0;
        }
    } else {
        srgb = clamp(texelFetch(input_a, ip, 0).rgb, 0.0, 1.0);
    }
    if (kind == kFlipSrgb || kind == kFlipBackProject)
        lin = vec3(flip_srgb_to_linear(srgb.r), flip_srgb_to_linear(srgb.g),
                   flip_srgb_to_linear(srgb.b));
    imageStore(opponent, int(p.y * size.x + p.x), vec4(flip_linear_rgb_to_ycxcz(lin), valid));
}
