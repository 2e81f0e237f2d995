#version 450
// Meng 2018 pass I, part 1: the LP texels whose screen point lies on (or within 1.5 texel
// footprints of) the screen, appended to a compacted list. With L from the farthest corner,
// about half of the buffer maps off screen; the shading pass dispatches only the listed texels.
#extension GL_GOOGLE_include_directive : require
#include "kfr_map.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, set = 0, binding = 0) buffer TexelList {
    uint dispatch[3];
    uint count;
    uint items[];  // u | v << 16
} list;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(vec2(t), kfr.lp_size))) return;
    vec2 lp = vec2(t) + 0.5;
    vec2 p = kfr_inverse(lp);
    float fp = max(kfr_texel_footprint(lp.x), 1.0);
    // Texels just off the border still feed the inverse pass's bilinear taps at the border.
    vec2 outside = max(max(-p, p - kfr.screen), vec2(0.0));
    if (max(outside.x, outside.y) <= 1.5 * fp) {
        uint slot = atomicAdd(list.count, 1u);
        list.items[slot] = uint(t.x) | (uint(t.y) << 16u);
    }
}
