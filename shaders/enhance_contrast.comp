#version 450
#extension GL_GOOGLE_include_directive : require
// Enhancement pass 3: Patney 2016's contrast enhancement on display luminance,
// Y' + f_e(1 + σ)(Y' − I_avg), I_avg from the Gaussian pyramid at LOD = log2(1 + √2σ), σ the blur
// the pixel's shading rate stands for; the luminance change is added to every channel after
// gamma and the result decoded back to linear HDR. Mirrors contrast_enhance().
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, r16f) uniform readonly image2D rate_in;
layout(set = 0, binding = 2) uniform sampler2D pyramid;  // trilinear, clamp to edge
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D color_out;

layout(push_constant) uniform Push {
    float f_e;
    int levels;
} pc;

#include "enhance_common.glsl"

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(color_in);
    if (any(greaterThanEqual(p, size))) return;
    vec2 px = vec2(p) + 0.5;
    vec2 full = vec2(size);
    vec4 c = imageLoad(color_in, p);
    vec3 d = vec3(enh_display_encode(c.r), enh_display_encode(c.g), enh_display_encode(c.b));
    float y = clamp(enh_luma(d), 0.0, 1.0);
    float sigma = enh_blur_sigma_for_rate(imageLoad(rate_in, p).x);
    float lod = sigma > 0.0 ? min(log2(1.0 + 1.41421356 * sigma), float(pc.levels - 1)) : 0.0;
    // The sampler's trilinear filter blends the two pyramid levels around the LOD (the model's
    // sample_trilinear): one filtered fetch instead of a loop over levels with 8 texel loads.
    float avg = clamp(textureLod(pyramid, px / full, lod).x, 0.0, 1.0);
    float gain = pc.f_e * min(1.0 + sigma, 16.0);
    float y_out = clamp(y + gain * (y - avg), 0.0, 1.0);
    vec3 d_out = clamp(d + (y_out - y), 0.0, 1.0);
    imageStore(color_out, p, vec4(enh_display_decode(d_out.r), enh_display_decode(d_out.g),
                                  enh_display_decode(d_out.b), c.a));
}
