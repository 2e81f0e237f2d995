// TAA pass 1: first two raw moments of the tone-mapped YCoCg colour over 3×3 (Patney §4.2),
// levels 0 and 1 of the moment mip chain in one dispatch. Each 8×8 group converts its 10×10
// footprint once into shared memory (not 9 times per pixel), then the 2×2 box of level 1 comes
// from the group's own level-0 moments as stored (rounded to TAA_FORMAT), exactly what
// taa_reduce.glsl would read back. TAA_FORMAT is rgba16f or rgba32f (the wrapper files);
// TAA_STORED(v) rounds like that storage.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, TAA_FORMAT) uniform writeonly image2D m1_out;
layout(set = 0, binding = 2, TAA_FORMAT) uniform writeonly image2D m2_out;
layout(set = 0, binding = 3, TAA_FORMAT) uniform writeonly image2D m1_level1;
layout(set = 0, binding = 4, TAA_FORMAT) uniform writeonly image2D m2_level1;

#include "taa_common.glsl"

shared vec3 tile[10][10];
shared vec3 tile_m1[8][8];
shared vec3 tile_m2[8][8];

void main() {
    ivec2 size = imageSize(color_in);
    ivec2 origin = ivec2(gl_WorkGroupID.xy) * 8;
    ivec2 l = ivec2(gl_LocalInvocationID.xy);
    for (uint i = gl_LocalInvocationIndex; i < 100u; i += 64u) {
        ivec2 q = clamp(origin + ivec2(int(i % 10u), int(i / 10u)) - 1, ivec2(0), size - 1);
        tile[i / 10u][i % 10u] = taa_rgb_to_ycocg(taa_tonemap(imageLoad(color_in, q).rgb));
    }
    barrier();
    vec3 m1 = vec3(0.0);
    vec3 m2 = vec3(0.0);
    for (int dy = 0; dy < 3; ++dy) {
        for (int dx = 0; dx < 3; ++dx) {
            vec3 c = tile[l.y + dy][l.x + dx];
            m1 += c;
            m2 += c * c;
        }
    }
    m1 = TAA_STORED(m1 * (1.0 / 9.0));
    m2 = TAA_STORED(m2 * (1.0 / 9.0));
    ivec2 p = origin + l;
    if (all(lessThan(p, size))) {
        imageStore(m1_out, p, vec4(m1, 0.0));
        imageStore(m2_out, p, vec4(m2, 0.0));
    }
    tile_m1[l.y][l.x] = m1;
    tile_m2[l.y][l.x] = m2;
    barrier();
    // Level 1 (Vulkan mip size): texel t averages level-0 texels 2t, 2t+1 clamped to the last
    // one; both lie in this group because groups start at even coordinates.
    ivec2 t = p / 2;
    if (any(notEqual(l & 1, ivec2(0))) || any(greaterThanEqual(t, imageSize(m1_level1)))) return;
    ivec2 a = min(p, size - 1) - origin;
    ivec2 b = min(p + 1, size - 1) - origin;
    vec3 s1 = tile_m1[a.y][a.x] + tile_m1[a.y][b.x] + tile_m1[b.y][a.x] + tile_m1[b.y][b.x];
    vec3 s2 = tile_m2[a.y][a.x] + tile_m2[a.y][b.x] + tile_m2[b.y][a.x] + tile_m2[b.y][b.x];
    imageStore(m1_level1, t, vec4(0.25 * s1, 0.0));
    imageStore(m2_level1, t, vec4(0.25 * s2, 0.0));
}
