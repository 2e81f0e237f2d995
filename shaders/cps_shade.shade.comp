#version 450
// Coarse pixel shading, pass 2 (one dispatch per list, indirect): one shade per coarse pixel
// (rate x rate pixels) from the full-resolution G-buffer sample at its centre, broadcast to the
// pixels on the same surface. Lists 0-2 call the host shading function; pixels of another surface
// (material id, depth or normal discontinuity: visibility stays at full rate) go to the edge
// list for pass 3. Built a second time with FOVEA_CPS_BACKGROUND for the background-only lists
// 4-6: the host's environment function fovea_background(), no edges (one surface: the sky).
// Writes the method's persistent colour image (copied to the frame output after pass 3).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
#include "fovea_frame.glsl"
#include "cps_common.glsl"
#include "fovea_host.glsl"
layout(set = 1, binding = 3, rgba16f) uniform writeonly image2D cps_color;

shared uint s_shaded;

bool same_surface(FoveaGSample a, FoveaGSample b) {
    if (a.background || b.background) return a.background == b.background;
    if (abs(a.material.x - b.material.x) > 0.5) return false;
    if (abs(a.distance - b.distance) > 0.02 * a.distance + 0.01) return false;
    return dot(a.normal, b.normal) > 0.8;
}

void main() {
    if (gl_LocalInvocationIndex == 0u) s_shaded = 0u;
    barrier();
    uint list = cps_push.list;
    uint cls = cps_list_rate_class(list);
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
            atomicAdd(s_shaded, 1u);
            cps_add_luminance(tile, c.rgb);
            for (int y = o.y; y < hi.y; ++y) {
                for (int x = o.x; x < hi.x; ++x) {
                    ivec2 p = ivec2(x, y);
                    bool same = r == 1 || (p == a) || same_surface(g, fovea_load_gsample(p));
                    if (!same) {
                        uint idx = atomicAdd(cps_args.count[kCpsEdgeList], 1u);
                        if (idx < cps_push.edge_capacity) {
                            cps_edges.px[idx] = uint(x) | (uint(y) << 15) | (cls << 30);
                            atomicMax(cps_args.cmd[kCpsEdgeList].x, idx / 64u + 1u);
                            continue;
                        }
                        atomicAdd(cps_args.dropped, 1u);
                    }
                    imageStore(cps_color, p, c);
                }
            }
#endif
        }
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && s_shaded > 0u)
        atomicAdd(fovea_stats.shaded_samples, s_shaded);
}
