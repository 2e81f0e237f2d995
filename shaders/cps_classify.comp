#version 450
// Coarse pixel shading, pass 1: one thread per tile (acuity.tile_size, 16x16 by default)
// decides, before anything is shaded, what the tile needs this frame, appends it to one
// compacted list and grows that list's indirect dispatch so the later passes launch exactly one
// thread per coarse pixel of the listed tiles; a tile in no list costs no thread.
//
// The classes, tested in this order (the "skip" ones only with option cps.skip=1, the default):
//  reused      still and converged: no motion in the tile (|motion + jitter| or |motion| <=
//              still_px: none beyond the sub-pixel jitter), camera position unchanged,
//              consecutive frame without a cut, the acuity rate the tile was shaded at
//              unchanged, its eccentricity moved less than ecc_deg since, and shaded in
//              >= converge_frames such frames.
//              Last frame's shading stays in the method's persistent colour image: no list.
//              Every refresh_frames-th frame (staggered per tile) the tile is re-shaded anyway,
//              so a host whose shading animates (fovea_frame.time) is never frozen for long.
//  background  every pixel without geometry (position.w == 0) and the host defines
//              fovea_background(): lists 4-6, the environment function at the tile's rate; the
//              host shading function is not called.
//  flat or     last frame's shading of the tile, done at its acuity rate, has a luminance range
//  saturated   (cps_luminance, left by its shade samples) with contrast (max - min) / (max + min)
//              below flat_contrast, or every sample at or above `saturated` (beyond display
//              white): the coarsest rate whatever the eccentricity (Stengel 2016's adaptation
//              term). A tile shaded coarser than its acuity rate is not measured again next
//              frame (it would always look flat).
//  rate 1/2/4  the acuity model's rate for the tile (fovea_tile_rate): lists 0-2.
// Independently, "no detail to extend" (background, flat or saturated) is written per tile to
// cps_no_detail for passes that add detail (enhancement), and counted.
// The rate S_t of every shaded pixel is written here to the method's persistent S_t image
// (reused tiles keep theirs); both persistent images are copied to the frame outputs at the end.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
#include "fovea_frame.glsl"
#include "cps_common.glsl"
layout(set = 1, binding = 3, r8ui) uniform writeonly uimage2D cps_rate_tiles;
layout(set = 1, binding = 7, r16f) uniform writeonly image2D cps_rate;  // S_t, persistent
// Per tile, persistent across frames: x = stored shading (bits 0-1 rate class used, 2-3 acuity
// class then, 4 valid, 5 shaded at its acuity rate, 6 background), y = consecutive still frames
// at that rate, z = eccentricity (float bits) when shaded.
layout(std430, set = 1, binding = 5) buffer CpsTileState { uvec4 s[]; } cps_state;
layout(std430, set = 1, binding = 6) buffer CpsNoDetail { uint flag[]; } cps_no_detail;

const uint kValid = 16u, kAtAcuity = 32u, kBackground = 64u;

void main() {
    uint tile = gl_GlobalInvocationID.x;  // one thread per tile: no barriers (costly on a CPU)
    if (tile >= cps_push.tiles_x * cps_push.tiles_y) return;
    uint tx = tile % cps_push.tiles_x;
    uint ty = tile / cps_push.tiles_x;
    int ts = int(fovea_frame.acuity.tile_size);
    ivec2 lo = ivec2(int(tx), int(ty)) * ts;
    ivec2 hi = min(lo + ivec2(ts), ivec2(fovea_frame.extent));
    bool skip = (cps_push.flags & kCpsSkip) != 0u;
    // Image loads dominate this pass on a CPU device: each image is read only when its answer
    // can change the tile's class (motion: reuse possible; position: not reused and the host
    // has fovea_background()), and each loop stops at the first pixel that decides.

    // 1. Still: no pixel moves. A still pixel's motion is -jitter (the jittered sample against
    // the previous unjittered view) or 0 (hosts that leave the jitter out, as the demo does for
    // the sky): the smaller of the two counts.
    bool may_reuse = skip && (cps_push.flags & kCpsReuse) != 0u &&
                     (cps_push.flags & (kCpsHistory | kCpsCameraStill)) ==
                         (kCpsHistory | kCpsCameraStill);
    bool motionless = may_reuse;
    for (int y = lo.y; y < hi.y && motionless; ++y) {
        for (int x = lo.x; x < hi.x; ++x) {
            vec2 m = imageLoad(fovea_g_motion, ivec2(x, y)).xy;
            vec2 mj = abs(m + fovea_frame.jitter_px);
            m = abs(m);
            if (min(max(m.x, m.y), max(mj.x, mj.y)) > cps_push.still_px) {
                motionless = false;
                break;
            }
        }
    }

    // 2. Reuse, from the motion and the tile's stored state.
    float r = fovea_tile_rate(fovea_frame.display, fovea_frame.acuity, vec2(lo), vec2(hi),
                              fovea_frame.gaze_px);
    uint acuity = r >= 4.0 ? 2u : (r >= 2.0 ? 1u : 0u);
    float ecc = fovea_eccentricity_deg(fovea_frame.display, (vec2(lo) + vec2(hi)) * 0.5,
                                       fovea_frame.gaze_px);
    uvec4 st = cps_state.s[tile];
    bool history = skip && (cps_push.flags & kCpsHistory) != 0u && (st.x & kValid) != 0u;
    bool still = history && motionless && ((st.x >> 2) & 3u) == acuity;
    bool refresh = cps_push.refresh_frames > 0u &&
                   (cps_push.frame + tile * 7919u) % cps_push.refresh_frames == 0u;
    bool reused = still && !refresh && st.y >= cps_push.converge_frames &&
                  abs(uintBitsToFloat(st.z) - ecc) < cps_push.ecc_deg;

    // 3. Background: no pixel with geometry (a reused tile keeps what it was).
    bool background = reused && (st.x & kBackground) != 0u;
    if (!reused && skip && (cps_push.flags & kCpsHostBackground) != 0u) {
        background = true;
        for (int y = lo.y; y < hi.y && background; ++y) {
            for (int x = lo.x; x < hi.x; ++x) {
                if (imageLoad(fovea_g_position, ivec2(x, y)).w > 0.0) {
                    background = false;
                    break;
                }
            }
        }
    }

    bool is_flat = false;
    if (history && (st.x & kAtAcuity) != 0u) {
        float lmin = uintBitsToFloat(cps_luminance.range[tile].x);
        float lmax = uintBitsToFloat(cps_luminance.range[tile].y);
        is_flat = lmax - lmin <= cps_push.flat_contrast * (lmax + lmin) ||
                  lmin >= cps_push.saturated;
    }
    cps_no_detail.flag[tile] = (background || is_flat) ? 1u : 0u;
    if (background || is_flat) atomicAdd(fovea_stats.no_detail_tiles, 1u);

    uint used;
    if (reused) {
        used = st.x & 3u;  // no list: the stored shading and S_t stay
        atomicAdd(fovea_stats.reused_tiles, 1u);
        atomicAdd(fovea_stats.tiles[3], 1u);
    } else {
        uint cls = is_flat ? 2u : acuity;
        bool env = background && (cps_push.flags & kCpsHostBackground) != 0u;
        uint list = env ? kCpsBackgroundList + cls : cls;
        uint slot = atomicAdd(cps_args.count[list], 1u);
        cps_lists.tile[cps_list_base(list) * cps_push.capacity + slot] = tile;
        uint side = uint(ts) >> cls;
        atomicMax(cps_args.cmd[list].x, ((slot + 1u) * side * side + kCpsGroupSize - 1u) /
                                             kCpsGroupSize);
        if (env) {
            atomicAdd(fovea_stats.background_tiles, 1u);
            atomicAdd(fovea_stats.tiles[3], 1u);
        } else {
            atomicAdd(fovea_stats.tiles[cls], 1u);
            // The shade pass calls the host function once per coarse pixel of the tile inside
            // the frame; counted here so that pass needs no workgroup counter.
            uint px = 1u << cls;  // coarse pixel edge
            uvec2 coarse = (uvec2(hi - lo) + uvec2(px - 1u)) / px;
            atomicAdd(fovea_stats.shaded_samples, coarse.x * coarse.y);
        }
        if (is_flat && acuity != 2u) atomicAdd(fovea_stats.flat_tiles, 1u);
        uint count = still ? min(st.y + 1u, 255u) : 1u;
        cps_state.s[tile] = uvec4(cls | (acuity << 2) | kValid |
                                      (cls == acuity ? kAtAcuity : 0u) |
                                      (background ? kBackground : 0u),
                                  count, floatBitsToUint(ecc), 0u);
        cps_luminance.range[tile] = uvec2(0x7f800000u, 0u);  // +inf, 0: the passes fill it
        used = cls;
        float s = fovea_normalized_rate(float(1u << cls));
        for (int y = lo.y; y < hi.y; ++y)
            for (int x = lo.x; x < hi.x; ++x) imageStore(cps_rate, ivec2(x, y), vec4(s));
    }
    imageStore(cps_rate_tiles, ivec2(int(tx), int(ty)),
               uvec4(used == acuity ? uint(r) : (1u << used)));
}
