#version 450
// TAA pass 3: sorts the resolve's 8×8 tiles into two lists, one thread per tile. A tile goes to
// the foveal list when any of its pixels reads level 0 of the moment chain (LOD = 4·S_t < 1: the
// pixel's own 3×3 window), else to the peripheral list; each list's indirect dispatch grows by
// one workgroup per tile. lavapipe runs every line of a shader for every lane (a branch only masks
// lanes), so the 3×3 window costs every pixel it is compiled into: only the foveal resolve
// pipeline has it. Same LOD rule as taa_resolve.glsl (NaN/inf S_t counts as 1).
layout(local_size_x = 64) in;
layout(set = 0, binding = 0, r16f) uniform readonly image2D rate_in;
layout(std430, set = 0, binding = 1) buffer TaaTileArgs {
    uvec4 cmd[2];  // VkDispatchIndirectCommand x, y, z (+ pad): 0 foveal, 1 peripheral
} args;
layout(std430, set = 0, binding = 2) buffer TaaTileLists { uint tile[]; } lists;  // [2][capacity]

layout(push_constant) uniform Push {
    uint tiles_x;
    uint tiles_y;
    int levels;  // moment chain levels (LOD clamps to levels - 1)
} pc;

const int kTile = 8;  // the resolve's workgroup

void main() {
    uint tile = gl_GlobalInvocationID.x;
    uint capacity = pc.tiles_x * pc.tiles_y;
    if (tile >= capacity) return;
    ivec2 lo = ivec2(int(tile % pc.tiles_x), int(tile / pc.tiles_x)) * kTile;
    ivec2 hi = min(lo + ivec2(kTile), imageSize(rate_in));
    float max_lod = float(pc.levels - 1);
    bool foveal = false;
    for (int y = lo.y; y < hi.y && !foveal; ++y) {
        for (int x = lo.x; x < hi.x; ++x) {
            float s = imageLoad(rate_in, ivec2(x, y)).x;
            s = (isnan(s) || isinf(s)) ? 1.0 : clamp(s, 0.0, 1.0);
            if (min(4.0 * s, max_lod) < 1.0) {
                foveal = true;
                break;
            }
        }
    }
    uint list = foveal ? 0u : 1u;
    uint slot = atomicAdd(args.cmd[list].x, 1u);
    lists.tile[list * capacity + slot] = tile;
}
