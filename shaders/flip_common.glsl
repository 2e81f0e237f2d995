// LDR-FLIP on the GPU (Andersson et al. 2020, erratum: the achromatic channel is divided by 116),
// shared by shaders/flip_*.comp. The colour constants come from the CPU reference
// (metrics/src/flip_filters.hpp) through FlipColour; the kernels per ppd level through
// FlipAxes/FlipWeights, built by the same code the CPU reference filters with
// (metrics/src/gpu_flip.cpp). Every pixel's ppd is uniform over the 16 x 16 block it lies in: all
// of a block's pixels read one kernel per axis.

const uint kFlipBlock = 16u;

struct FlipAxis {
    int colour_radius;
    int feature_radius;
    uint colour_offset;   // first of 2 colour_radius + 1 vec4 taps (y, cx, cz1, cz2) in weights
    uint feature_offset;  // first of 2 feature_radius + 1 vec4 taps (g, dg, ddg, 0)
    float cz1_sum;        // the blue-yellow kernel's two raw parts' sums (2-D normalisation)
    float cz2_sum;
    float reserved0;
    float reserved1;
};

// The axis of one 16-pixel block: `axes` is the FlipAxis table as a texel buffer (two uvec4 per
// entry), `block_axis` the entry of each block.
FlipAxis flip_axis(usamplerBuffer axes, usamplerBuffer block_axis, uint block) {
    int i = int(texelFetch(block_axis, int(block)).x);
    uvec4 a = texelFetch(axes, 2 * i), b = texelFetch(axes, 2 * i + 1);
    return FlipAxis(int(a.x), int(a.y), a.z, a.w, uintBitsToFloat(b.x), uintBitsToFloat(b.y), 0.0,
                    0.0);
}

// What an input texel holds.
const uint kFlipSrgb = 0u;         // sRGB-encoded values (an RGBA8 UNORM upload, or floats 0..1)
const uint kFlipDemoDisplay = 1u;  // linear HDR: the demo's display transform, 8-bit rounded
const uint kFlipBackProject = 2u;  // a previous frame (kFlipDemoDisplay) back-projected
const uint kFlipSrgb8 = 3u;        // kFlipSrgb from an 8-bit UNORM image (the host picks it)

float flip_srgb_to_linear(float v) {
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

// demo::tonemap (tools/demo/metrics.cpp): 1 - e^-c, sRGB encode, rounded to 8 bits: the codes.
vec3 flip_demo_code(vec3 c) {
    vec3 s;
    for (int k = 0; k < 3; ++k) {
        if (!(c[k] > 0.0)) {
            s[k] = 0.0;
            continue;
        }
        float t = 1.0 - exp(-c[k]);
        float e = t <= 0.0031308 ? 12.92 * t : 1.055 * pow(t, 1.0 / 2.4) - 0.055;
        s[k] = floor(clamp(e * 255.0 + 0.5, 0.0, 255.0));
    }
    return s;
}

vec3 flip_demo_display(vec3 c) { return flip_demo_code(c) / 255.0; }
