#version 450
#extension GL_GOOGLE_include_directive : require
// Enhancement pass 3: Patney 2016's contrast enhancement on display luminance,
// Y' + f_e(1 + σ)(Y' − I_avg), I_avg from the Gaussian pyramid at LOD = log2(1 + √2σ), σ the blur
// the pixel's shading rate stands for; the luminance change is added to every channel after
// gamma and the result decoded back to linear HDR. Mirrors contrast_enhance().
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, r16f) uniform readonly image2D rate_in;
layout(set = 0, binding = 2) uniform sampler2D pyramid;  // texelFetch only
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D color_out;

layout(push_constant) uniform Push {
    float f_e;
    int levels;
} pc;

#include "enhance_common.glsl"

float fetch_level(vec2 px, vec2 full, int level) {
    ivec2 size = textureSize(pyramid, level);
    vec2 f = px / full * vec2(size) - 0.5;
    vec2 b = floor(f);
    vec2 a = f - b;
    ivec2 i0 = ivec2(b);
    ivec2 hi = size - 1;
    float s00 = texelFetch(pyramid, clamp(i0, ivec2(0), hi), level).x;
    float s10 = texelFetch(pyramid, clamp(i0 + ivec2(1, 0), ivec2(0), hi), level).x;
    float s01 = texelFetch(pyramid, clamp(i0 + ivec2(0, 1), ivec2(0), hi), level).x;
    float s11 = texelFetch(pyramid, clamp(i0 + ivec2(1, 1), ivec2(0), hi), level).x;
    return mix(mix(s00, s10, a.x), mix(s01, s11, a.x), a.y);
}

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
    int l0 = int(floor(lod));
    float t = lod - float(l0);
    // Uniform level index in texelFetch (lavapipe mis-fetches per-invocation levels).
    float a = 0.0;
    float b = 0.0;
    for (int l = 0; l < pc.levels; ++l) {
        if (l != l0 && l != l0 + 1) continue;
        float v = fetch_level(px, full, l);
        if (l == l0) a = v;
        if (l == l0 + 1) b = v;
    }
    float avg = clamp(t > 0.0 ? a + (b - a) * t : a, 0.0, 1.0);
    float gain = pc.f_e * min(1.0 + sigma, 16.0);
    float y_out = clamp(y + gain * (y - avg), 0.0, 1.0);
    vec3 d_out = clamp(d + (y_out - y), 0.0, 1.0);
    imageStore(color_out, p, vec4(enh_display_decode(d_out.r), enh_display_decode(d_out.g),
                                  enh_display_decode(d_out.b), c.a));
}
