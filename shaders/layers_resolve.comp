#version 450
// Guenter 2012 Fig. 6: the jittered layer samples are resampled onto the layer's unjittered grid
// and blended with the temporally reprojected history of the layer (clamped to the current
// 3x3 neighbourhood so disocclusions and lighting changes do not ghost).
#extension GL_GOOGLE_include_directive : require
#include "layers_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D current;
layout(set = 0, binding = 1, rg16f) uniform readonly image2D motion;   // layer G-buffer motion
layout(set = 0, binding = 2, rgba16f) uniform readonly image2D history_in;
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D history_out;
layout(set = 0, binding = 4, rgba16f) uniform writeonly image2D composite_in;  // fixed per layer

layout(push_constant) uniform ResolvePush {
    vec2 origin;       // this frame's layer origin, display pixels
    vec2 prev_origin;  // the history's origin
    vec2 jitter;       // this frame's jitter, layer texels
    float s;
    float alpha;       // weight of the current frame (1: no history)
    int has_history;
    float pad0;
    vec2 view_jitter;  // the jitter the host rendered this layer with, layer texels
} rp;

vec4 load_clamped(ivec2 t) {
    return imageLoad(current, clamp(t, ivec2(0), imageSize(current) - 1));
}

vec4 bilinear_current(vec2 f) {
    ivec2 b = ivec2(floor(f));
    vec2 w = f - vec2(b);
    return mix(mix(load_clamped(b), load_clamped(b + ivec2(1, 0)), w.x),
               mix(load_clamped(b + ivec2(0, 1)), load_clamped(b + ivec2(1, 1)), w.x), w.y);
}

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(history_out);
    if (any(greaterThanEqual(t, size))) return;
    // Sample k of this frame sits at layer coordinate k + 0.5 + jitter: the grid point t + 0.5
    // is at continuous index t - jitter.
    vec4 cur = bilinear_current(vec2(t) - rp.jitter);
    vec4 result = cur;
    if (rp.has_history != 0 && rp.alpha < 1.0) {
        vec2 centre = rp.origin + (vec2(t) + 0.5) * rp.s;
        // Motion (G-buffer contract, as TAA reads it) runs from a texel's unjittered centre to
        // the previous position of the jittered sample: the flow at the sample is motion + jitter.
        vec2 m = imageLoad(motion, clamp(ivec2(vec2(t) - rp.jitter + 0.5), ivec2(0),
                                         imageSize(motion) - 1)).xy;
        vec2 prev = centre - (m + rp.view_jitter) * rp.s;
        vec2 h = (prev - rp.prev_origin) / rp.s - 0.5;
        if (all(greaterThanEqual(h, vec2(0.0))) && all(lessThanEqual(h, vec2(size - 1)))) {
            ivec2 hb = ivec2(floor(h));
            vec2 w = h - vec2(hb);
            ivec2 hmax = size - 1;
            vec4 h00 = imageLoad(history_in, hb);
            vec4 h10 = imageLoad(history_in, min(hb + ivec2(1, 0), hmax));
            vec4 h01 = imageLoad(history_in, min(hb + ivec2(0, 1), hmax));
            vec4 h11 = imageLoad(history_in, min(hb + ivec2(1, 1), hmax));
            vec4 hist = mix(mix(h00, h10, w.x), mix(h01, h11, w.x), w.y);
            vec4 lo = cur, hi = cur;
            ivec2 c = ivec2(floor(vec2(t) - rp.jitter + 0.5));
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    vec4 n = load_clamped(c + ivec2(dx, dy));
                    lo = min(lo, n);
                    hi = max(hi, n);
                }
            result = mix(clamp(hist, lo, hi), cur, rp.alpha);
        }
    }
    imageStore(history_out, t, vec4(result.rgb, 1.0));
    imageStore(composite_in, t, vec4(result.rgb, 1.0));
}
