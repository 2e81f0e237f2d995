#version 450
// Coarse pixel shading, pass 2 (one dispatch per list, indirect): one shade per coarse pixel
// (rate x rate pixels) from the full-resolution G-buffer sample at its centre, written to all
// its pixels. Lists 0-2 call the host shading function; pixels of another surface (material id,
// depth or normal discontinuity: visibility stays at full rate) go to the edge list, and pass 3
// overwrites them with their own shade. Built once per list 0-2 with CPS_RATE_CLASS = the list's
// rate class, and once with FOVEA_CPS_BACKGROUND for the background-only lists 4-6: the host's
// environment function fovea_background(), no edges (one surface: the sky).
// Writes the method's persistent colour image (copied to the frame output after pass 3).
// Pass 1 already counted this pass's shades (fovea_stats.shaded_samples): no shared counter,
// so no workgroup barrier (each costs a coroutine switch per 8 lanes on llvmpipe).
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "cps_common.glsl"
layout(local_size_x = CPS_GROUP_SIZE) in;
#include "fovea_host.glsl"
layout(set = 1, binding = 3, rgba16f) uniform writeonly image2D cps_color;

bool same_surface(FoveaGSample a, FoveaGSample b) {
    if (a.background || b.background) return a.background == b.background;
    if (abs(a.material.x - b.material.x) > 0.5) return false;
    if (abs(a.distance - b.distance) > 0.02 * a.distance + 0.01) return false;
    return dot(a.normal, b.normal) > 0.8;
}

void main() {
    uint list = cps_push.list;
#ifdef CPS_RATE_CLASS
    // One pipeline per host-function list: the rate is a constant, so the 1x1 list carries no
    // surface test or edge code and the r x r loops unroll (llvmpipe runs both sides of a
    // branch, so a run-time r == 1 saved nothing).
    const uint cls = CPS_RATE_CLASS;
#else
    uint cls = cps_list_rate_class(list);
#endif
    int r = 1 << int(cls);
    uint ts = uint(fovea_frame.acuity.tile_size);
    uint side = ts >> cls;
    uint per = side * side;
    uint gi = gl_GlobalInvocationID.x;
    uint slot = gi / per;
    uint within = gi % per;
    ivec2 ext = ivec2(fovea_frame.extent);
    if (slot < cps_args.count[list]) {
        uint tile = cps_lists.tile[cps_list_base(list) * cps_push.capacity + slot];
        ivec2 o = ivec2(int(tile % cps_push.tiles_x), int(tile / cps_push.tiles_x)) * int(ts) +
                  ivec2(int(within % side), int(within / side)) * r;
        if (o.x < ext.x && o.y < ext.y) {
            ivec2 hi = min(o + ivec2(r), ext);
            ivec2 a = min(o + ivec2(r / 2), hi - ivec2(1));
            FoveaGSample g = fovea_load_gsample(a);
            float s = fovea_normalized_rate(float(r));
            FoveaFootprint fp = fovea_make_footprint((vec2(o) + vec2(hi)) * 0.5, float(r),
                                                     g.distance, s);
#ifdef FOVEA_CPS_BACKGROUND
            vec4 c = vec4(fovea_background(g, fp), 1.0);
            cps_add_luminance(tile, c.rgb);
            for (int y = o.y; y < hi.y; ++y)
                for (int x = o.x; x < hi.x; ++x) imageStore(cps_color, ivec2(x, y), c);
#else
            vec4 c = vec4(fovea_shade(g, fp), 1.0);
            cps_add_luminance(tile, c.rgb);
            // Every pixel takes the coarse shade (pass 3 overwrites the edge pixels: no branch
            // around the store); pixels of another surface, one bit each (r x r <= 16), go to
            // the edge list with one atomic per coarse pixel, not one per pixel (atomics are
            // slow on a CPU).
            uint edges = 0u;
            for (int y = o.y; y < hi.y; ++y) {
                for (int x = o.x; x < hi.x; ++x) {
                    ivec2 p = ivec2(x, y);
                    imageStore(cps_color, p, c);
                    if (!(r == 1 || p == a || same_surface(g, fovea_load_gsample(p))))
                        edges |= 1u << uint((y - o.y) * r + (x - o.x));
                }
            }
            if (edges != 0u) {
                uint n = uint(bitCount(edges));
                uint base = atomicAdd(cps_args.count[kCpsEdgeList], n);
                uint cap = cps_push.edge_capacity;
                if (base < cap)
                    atomicMax(cps_args.cmd[kCpsEdgeList].x,
                              (min(base + n, cap) - 1u) / kCpsGroupSize + 1u);
                if (base + n > cap) atomicAdd(cps_args.dropped, base + n - max(base, cap));
                for (uint idx = base; edges != 0u && idx < cap; ++idx) {
                    int bit = findLSB(edges);
                    edges &= edges - 1u;
                    ivec2 p = o + ivec2(bit % r, bit / r);
                    cps_edges.px[idx] = uint(p.x) | (uint(p.y) << 15) | (cls << 30);
                }  // beyond the list's capacity a pixel keeps the coarse shade
            }
#endif
        }
    }
}
