#version 450
#extension GL_GOOGLE_include_directive : require
// Noise pass 3: sparse Gabor convolution at each pixel over the impulses of its 3×3 cells
// (Tariq 2022 §4.4), added to the display-referred (after gamma) value of every channel, i.e. a
// luminance-only change, then decoded back to linear HDR. Cells whose impulses all have zero
// amplitude (the fovea, flat regions) are skipped; a pixel with no noise is copied unchanged.
// Impulses and the strip lists are read through texel buffers: on lavapipe a texelFetch or a
// buffer imageLoad is one vector gather, while an SSBO or shared-memory load whose index differs
// between lanes is a loop of scalar loads, and the apply loop's indices do (each strip has its
// own list).
// Mirrors synthesize_gabor_noise() in sdk/src/vk/post/enhance_model.cpp.
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D color_out;
layout(set = 0, binding = 2) uniform samplerBuffer impulse;    // ix, iy, kx, ky (RGBA32F)
layout(set = 0, binding = 3) uniform samplerBuffer amplitude;  // K·w (R32F)
layout(set = 0, binding = 4) uniform samplerBuffer cell_peak;  // max |K·w| (R32F)
// This chunk's lists: per workgroup, kStrips lists of `cap` entries, global slot | block cell
// << 28 (slots < 2^28). Written and read by the same workgroup, behind a barrier.
layout(set = 0, binding = 5, r32ui) uniform coherent uimageBuffer strip_lists;

#include "enhance_common.glsl"
#include "enhance_noise_common.glsl"
#include "enhance_noise_push.glsl"

// With the cell edge r >= 15 px (checked on the host) the pixels of a 16x16 tile have at most
// 2x2 home cells, so their 3x3 neighbourhoods lie in one 4x4 block of cells.
const int kBlockCells = 4;

// Why per-strip lists: a pixel's 3x3 cells hold ~9/pi times the impulses its kernel disc can
// reach, and lavapipe runs every impulse of the loop for all lanes (a skipped one only masks
// them). The tile is cut into 8x4-pixel strips (lanes 0..7 of a row share one strip) and each
// strip keeps, in the 3x3 loop's order, only the impulses within reach of some pixel of it.
// What a pixel still visits is its 3x3 loop minus impulses it skipped anyway (d2 >= r2), so the
// sum is the same, term for term.
const ivec2 kStrip = ivec2(8, 4);
const int kStrips = (16 / 8) * (16 / 4);
shared int s_count[kStrips];

void main() {
    // Grid index (origin at cell (-1, -1)) of the home cell of the tile's first pixel; every
    // pixel of the tile has home + 1 - block_origin in [0, 1] per axis.
    ivec2 group = ivec2(gl_WorkGroupID.xy);
    ivec2 tile_first = (group + ivec2(pc.group_offset_x, pc.group_offset_y)) * 16;
    ivec2 block_origin = ivec2(floor((vec2(tile_first) + 0.5) / pc.radius));
    int lane = int(gl_LocalInvocationIndex);
    int cap = kBlockCells * kBlockCells * pc.per_cell;  // the most a strip can list
    int group_base = (group.y * pc.chunk_groups_x + group.x) * kStrips * cap;
    float r2 = pc.radius * pc.radius;
    if (lane < kStrips) {
        // Pixel centres of this strip; an impulse farther than r from all of them (with a
        // margin for rounding) adds to none.
        vec2 lo = vec2(tile_first + ivec2(lane % 2, lane / 2) * kStrip) + 0.5;
        vec2 hi = lo + vec2(kStrip - 1);
        float reach = r2 * 1.001 + 1.0;
        int n = 0;
        for (int cell = 0; cell < kBlockCells * kBlockCells; ++cell) {
            ivec2 g = block_origin + ivec2(cell % kBlockCells, cell / kBlockCells);
            if (any(greaterThanEqual(g, ivec2(pc.cells_x, pc.cells_y)))) continue;
            int index = g.y * pc.cells_x + g.x;
            if (!(texelFetch(cell_peak, index).x > 0.0)) continue;
            for (int k = 0; k < pc.per_cell; ++k) {
                int slot = index * pc.per_cell + k;
                if (texelFetch(amplitude, slot).x == 0.0) continue;
                vec2 at = texelFetch(impulse, slot).xy;
                vec2 gap = max(max(lo - at, at - hi), vec2(0.0));
                if (dot(gap, gap) >= reach) continue;
                uint entry = uint(slot) | (uint(cell) << 28);
                imageStore(strip_lists, group_base + lane * cap + n, uvec4(entry));
                ++n;
            }
        }
        s_count[lane] = n;
    }
    memoryBarrierImage();
    barrier();  // every invocation reaches both: the out-of-image return comes after

    ivec2 p = tile_first + ivec2(gl_LocalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(color_in)))) return;
    vec2 px = vec2(p) + 0.5;
    ivec2 home = ivec2(floor(px / pc.radius));
    ivec2 local_home = home - block_origin;  // in [0, 1]: its neighbourhood is local_home + 0..2
    float envelope = -kNoisePi * pc.bandwidth * pc.bandwidth;
    float acc = 0.0;
    ivec2 strip = ivec2(gl_LocalInvocationID.xy) / kStrip;
    int list = strip.y * 2 + strip.x;
    for (int i = 0; i < s_count[list]; ++i) {
        uint entry = imageLoad(strip_lists, group_base + list * cap + i).x;
        int cell = int(entry >> 28);
        ivec2 c = ivec2(cell % kBlockCells, cell / kBlockCells) - local_home;
        if (any(lessThan(c, ivec2(0))) || any(greaterThan(c, ivec2(2)))) continue;  // not its 3x3
        int slot = int(entry & 0x0fffffffu);
        vec4 imp = texelFetch(impulse, slot);
        vec2 d = px - imp.xy;
        float d2 = dot(d, d);
        if (d2 >= r2) continue;
        acc += texelFetch(amplitude, slot).x * exp(envelope * d2) * cos(dot(d, imp.zw));
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
