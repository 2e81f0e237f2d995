#version 450
// Meng 2018 pass I: shade every LP-buffer texel at the screen point it maps to, sampling the
// full-resolution G-buffer (nearest pixel). Texels that land well off screen are not shaded.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "fovea_host.glsl"
#include "kfr_map.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 1, binding = 0, rgba16f) uniform writeonly image2D lp_out;

shared uint group_shaded;

void main() {
    if (gl_LocalInvocationIndex == 0u) group_shaded = 0u;
    barrier();
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (all(lessThan(vec2(t), kfr.lp_size))) {
        vec2 lp = vec2(t) + 0.5;
        vec2 p = kfr_inverse(lp);
        float fp = max(kfr_texel_footprint(lp.x), 1.0);
        // Distance outside the screen; texels within ~1.5 footprints still feed the inverse
        // pass's bilinear taps at the border, so they are shaded at the clamped position.
        vec2 outside = max(max(-p, p - kfr.screen), vec2(0.0));
        vec4 c = vec4(0.0);
        if (max(outside.x, outside.y) <= 1.5 * fp) {
            vec2 q = clamp(p, vec2(0.0), kfr.screen - vec2(1e-3));
            ivec2 px = ivec2(q);
            FoveaGSample g = fovea_load_gsample(px);
            float s_t = clamp(log2(fp) * 0.5, 0.0, 1.0);
            FoveaFootprint f = fovea_make_footprint(vec2(px) + 0.5, fp, g.distance, s_t);
            c = vec4(fovea_shade(g, f), 1.0);
            atomicAdd(group_shaded, 1u);
        }
        imageStore(lp_out, t, c);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && group_shaded > 0u)
        atomicAdd(fovea_stats.shaded_samples, group_shaded);
}
