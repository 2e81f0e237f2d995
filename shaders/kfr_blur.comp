#version 450
// Meng 2018: 3x3 Gaussian in LP space on the peripheral columns (u >= blur_u0), where one LP
// texel covers more than a screen pixel; v wraps (the ±π seam is one neighbourhood), u clamps.
// Near the gaze, where LP rows are denser than screen pixels around the circle (u < aa_u1), the
// same [1 2 1] along v is the anti-aliasing prefilter for the inverse pass's bilinear tap.
#extension GL_GOOGLE_include_directive : require
#include "kfr_map.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D lp_in;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D lp_out;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(kfr.lp_size);
    if (any(greaterThanEqual(t, size))) return;
    // Branch-free (llvmpipe runs both sides of a branch): per-axis [1 2 1] or identity weights.
    float u = float(t.x) + 0.5;
    float blur_u = step(kfr.blur_u0, u);                 // periphery: smooth along u and v
    float blur_v = max(blur_u, 1.0 - step(kfr.aa_u1, u)); // minified near the gaze: along v
    vec4 sum = vec4(0.0);
    float wsum = 0.0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            ivec2 q = ivec2(clamp(t.x + dx, 0, size.x - 1), (t.y + dy + size.y) % size.y);
            vec4 s = imageLoad(lp_in, q);
            float wu = dx == 0 ? 2.0 : blur_u;
            float wv = dy == 0 ? 2.0 : blur_v;
            float w = wu * wv * s.a;  // a = 0: a texel that was not shaded
            sum += w * s;
            wsum += w;
        }
    imageStore(lp_out, t, wsum > 0.0 ? sum / wsum : vec4(0.0));
}
