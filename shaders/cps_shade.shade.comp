#version 450
// Coarse pixel shading, pass 2 (one dispatch per rate class, indirect): one host shade per coarse
// pixel (rate x rate pixels) from the full-resolution G-buffer sample at its centre, broadcast
// to the pixels on the same surface. Pixels of another surface (material id, depth or normal
// discontinuity: visibility stays at full rate) go to the edge list for pass 3.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
#include "fovea_frame.glsl"
#include "cps_common.glsl"
#include "fovea_host.glsl"

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
    uint cls = cps_push.cls;
    int r = 1 << int(cls);
    uint ts = uint(fovea_frame.acuity.tile_size);
    uint side = ts >> cls;
    uint per = side * side;
    uint gi = gl_GlobalInvocationID.x;
    uint slot = gi / per;
    uint within = gi % per;
    ivec2 ext = ivec2(fovea_frame.extent);
    if (slot < cps_args.count[cls]) {
        uint tile = cps_lists.tile[cls * cps_push.capacity + slot];
        ivec2 o = ivec2(int(tile % cps_push.tiles_x), int(tile / cps_push.tiles_x)) * int(ts) +
                  ivec2(int(within % side), int(within / side)) * r;
        if (o.x < ext.x && o.y < ext.y) {
            ivec2 hi = min(o + ivec2(r), ext);
            ivec2 a = min(o + ivec2(r / 2), hi - ivec2(1));
            FoveaGSample g = fovea_load_gsample(a);
            float s = fovea_normalized_rate(float(r));
            FoveaFootprint fp = fovea_make_footprint((vec2(o) + vec2(hi)) * 0.5, float(r),
                                                     g.distance, s);
            vec4 c = vec4(fovea_shade(g, fp), 1.0);
            atomicAdd(s_shaded, 1u);
            for (int y = o.y; y < hi.y; ++y) {
                for (int x = o.x; x < hi.x; ++x) {
                    ivec2 p = ivec2(x, y);
                    imageStore(fovea_out_rate, p, vec4(s));
                    bool same = r == 1 || (p == a) || same_surface(g, fovea_load_gsample(p));
                    if (!same) {
                        uint idx = atomicAdd(cps_args.count[3], 1u);
                        if (idx < cps_push.edge_capacity) {
                            cps_edges.px[idx] = uint(x) | (uint(y) << 15) | (cls << 30);
                            atomicMax(cps_args.cmd[3].x, idx / 64u + 1u);
                            continue;
                        }
                        atomicAdd(cps_args.dropped, 1u);
                    }
                    imageStore(fovea_out_color, p, c);
                }
            }
        }
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && s_shaded > 0u)
        atomicAdd(fovea_stats.shaded_samples, s_shaded);
}
