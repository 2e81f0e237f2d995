#version 450
// Stengel Eq. 10: one workgroup averages the tone-mapped luminance of the previous frame's
// low-resolution colour (pull-push level 3), weighted by acuity, and steps the exposure.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "adaptive_common.glsl"

layout(local_size_x = 256) in;
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D prev_low;
layout(std430, set = 1, binding = 1) buffer Exposure {
    float exposure;
    float l_avg;
    float pad[2];
} ex;

shared float s_sum[256];
shared float s_w[256];

void main() {
    uint i = gl_LocalInvocationIndex;
    ivec2 size = imageSize(prev_low);
    vec2 scale = fovea_frame.extent / vec2(size);
    float e = ex.exposure;
    float sum = 0.0, wsum = 0.0;
    for (int k = int(i); k < size.x * size.y; k += 256) {
        ivec2 t = ivec2(k % size.x, k / size.x);
        float w = adaptive_acuity((vec2(t) + 0.5) * scale);
        sum += adaptive_tonemap(adaptive_luminance(imageLoad(prev_low, t).rgb), e) * w;
        wsum += w;
    }
    s_sum[i] = sum;
    s_w[i] = wsum;
    barrier();
    for (uint s = 128u; s > 0u; s >>= 1u) {
        if (i < s) {
            s_sum[i] += s_sum[i + s];
            s_w[i] += s_w[i + s];
        }
        barrier();
    }
    float l = s_sum[0] / max(s_w[0], 1e-20);
    if (i == 0u && ad.has_history != 0 && s_w[0] > 0.0 && !isnan(l) && !isinf(l)) {
        ex.l_avg = l;
        ex.exposure = clamp(e + ad.adapt_rate * (ad.auto_exposure - l), 1e-3, 1e3);
    }
}
