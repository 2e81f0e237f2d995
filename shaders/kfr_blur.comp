#version 450
// Meng 2018: 3x3 Gaussian in LP space on the peripheral columns (u >= blur_u0), where one LP
// texel covers more than a screen pixel; v wraps (the ±π seam is one neighbourhood), u clamps.
#extension GL_GOOGLE_include_directive : require
#include "kfr_map.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D lp_in;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D lp_out;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = ivec2(kfr.lp_size);
    if (any(greaterThanEqual(t, size))) return;
    vec4 c = imageLoad(lp_in, t);
    if (float(t.x) + 0.5 >= kfr.blur_u0) {
        vec4 sum = vec4(0.0);
        float wsum = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                ivec2 q = ivec2(clamp(t.x + dx, 0, size.x - 1), (t.y + dy + size.y) % size.y);
                vec4 s = imageLoad(lp_in, q);
                float w = float((2 - abs(dx)) * (2 - abs(dy))) * s.a;  // a = 0: not shaded
                sum += w * s;
                wsum += w;
            }
        if (wsum > 0.0) c = sum / wsum;
    }
    imageStore(lp_out, t, c);
}
