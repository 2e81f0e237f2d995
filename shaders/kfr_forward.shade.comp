#version 450
// Meng 2018 pass I, part 2: shade the listed LP texels (indirect dispatch over the compacted
// list) at the screen point each maps to, sampling the full-resolution G-buffer (nearest
// pixel). The LP buffer was cleared, so unlisted texels keep alpha 0.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "fovea_host.glsl"
#include "kfr_map.glsl"

layout(local_size_x = 64) in;
layout(std430, set = 1, binding = 0) readonly buffer TexelList {
    uint dispatch[3];
    uint count;
    uint items[];
} list;
layout(set = 1, binding = 1, rgba16f) uniform writeonly image2D lp_out;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= list.count) return;
    uint packed = list.items[i];
    ivec2 t = ivec2(int(packed & 0xffffu), int(packed >> 16u));
    vec2 lp = vec2(t) + 0.5;
    vec2 p = clamp(kfr_inverse(lp), vec2(0.0), kfr.screen - vec2(1e-3));
    float fp = max(kfr_texel_footprint(lp.x), 1.0);
    ivec2 px = ivec2(p);
    FoveaGSample g = fovea_load_gsample(px);
    float s_t = clamp(log2(fp) * 0.5, 0.0, 1.0);
    FoveaFootprint f = fovea_make_footprint(vec2(px) + 0.5, fp, g.distance, s_t);
    vec3 c = fovea_shade(g, f);
    // Keep samples finite: the bilinear taps and the blur mix neighbours with zero weights, and
    // 0 · inf is NaN.
    c = min(mix(c, vec3(0.0), isnan(c)), vec3(65504.0));
    imageStore(lp_out, t, vec4(c, 1.0));
}
