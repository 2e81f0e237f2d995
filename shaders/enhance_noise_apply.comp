#version 450
#extension GL_GOOGLE_include_directive : require
// Noise pass 3: sparse Gabor convolution at each pixel over the impulses of its 3×3 cells
// (Tariq 2022 §4.4), added to the display-referred (after gamma) value of every channel, i.e. a
// luminance-only change, then decoded back to linear HDR. Cells whose impulses all have zero
// amplitude (the fovea, flat regions) are skipped; a pixel with no noise is copied unchanged.
// Mirrors synthesize_gabor_noise() in sdk/src/vk/post/enhance_model.cpp.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D color_out;
layout(std430, set = 0, binding = 2) readonly buffer Impulses { vec4 impulse[]; };
layout(std430, set = 0, binding = 3) readonly buffer Amplitudes { float amplitude[]; };
layout(std430, set = 0, binding = 4) readonly buffer Cells { float cell_peak[]; };

#include "enhance_common.glsl"
#include "enhance_noise_common.glsl"
#include "enhance_noise_push.glsl"

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(color_in)))) return;
    vec2 px = vec2(p) + 0.5;
    ivec2 home = ivec2(floor(px / pc.radius));
    float r2 = pc.radius * pc.radius;
    float envelope = -kNoisePi * pc.bandwidth * pc.bandwidth;
    float acc = 0.0;
    for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
            ivec2 c = home + ivec2(di, dj) + 1;  // grid origin is cell (-1, -1)
            int cell = c.y * pc.cells_x + c.x;
            if (!(cell_peak[cell] > 0.0)) continue;
            for (int k = 0; k < pc.per_cell; ++k) {
                int slot = cell * pc.per_cell + k;
                float w = amplitude[slot];
                if (w == 0.0) continue;
                vec4 imp = impulse[slot];
                vec2 d = px - imp.xy;
                float d2 = dot(d, d);
                if (d2 >= r2) continue;
                acc += w * exp(envelope * d2) * cos(dot(d, imp.zw));
            }
        }
    }
    vec4 colour = imageLoad(color_in, p);
    // Non-finite input becomes finite, as in the other enhancement passes; HDR stays HDR.
    colour = clamp(mix(colour, vec4(0.0), isnan(colour)), vec4(0.0), vec4(65504.0));
    if (acc == 0.0) {
        imageStore(color_out, p, colour);
        return;
    }
    float n = acc * pc.norm;
    vec3 d = vec3(enh_display_encode(colour.r), enh_display_encode(colour.g),
                  enh_display_encode(colour.b));
    d = clamp(d + n, 0.0, 1.0);
    imageStore(color_out, p, vec4(enh_display_decode(d.r), enh_display_decode(d.g),
                                  enh_display_decode(d.b), colour.a));
}
