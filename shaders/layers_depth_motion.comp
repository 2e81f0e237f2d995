#version 450
// Method "layers" on the forward path (IntegrationPath::kForwardLayers): the full-resolution
// depth and motion the post chain reads, taken from the innermost layer that covers the pixel
// (blend weight >= 1/2, the layer that also sets S_t in layers_composite.comp), nearest texel:
// depth and motion are never blended across layers. A layer's motion is in its own texels from
// its jittered grid; in display pixels the flow of the pixel's sample is (m + j_layer) * s, and
// the frame's convention subtracts the frame jitter again (projection.hpp).
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "layers_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const int LAYERS = 3;
// Inner layers 0..LAYERS-2 at bindings 0..2 (depth) and 4..6 (motion), the outer layer at 3
// and 7, as layers_composite.comp binds them (no dynamically indexed image arrays).
layout(set = 1, binding = 0, r32f) uniform readonly image2D depth0;
layout(set = 1, binding = 1, r32f) uniform readonly image2D depth1;
layout(set = 1, binding = 2, r32f) uniform readonly image2D depth2;
layout(set = 1, binding = 3, r32f) uniform readonly image2D depth_outer;
layout(set = 1, binding = 4, rg16f) uniform readonly image2D motion0;
layout(set = 1, binding = 5, rg16f) uniform readonly image2D motion1;
layout(set = 1, binding = 6, rg16f) uniform readonly image2D motion2;
layout(set = 1, binding = 7, rg16f) uniform readonly image2D motion_outer;
layout(set = 1, binding = 8, r32f) uniform writeonly image2D out_depth;
layout(set = 1, binding = 9, rg16f) uniform writeonly image2D out_motion;
layout(std430, set = 1, binding = 10) readonly buffer LayerTable {
    int count;
    int pad0, pad1, pad2;
    LayerInfo layer[4];
} table;
layout(push_constant) uniform DepthMotionPush {
    vec4 jitter[4];  // xy: each layer's jitter in its texels, as rendered
} dp;

// Texel of layer l (rendered with jitter j, in its texels) whose sample lies nearest the
// pixel's sample (its centre plus the frame jitter, where the composite reads colour): texel k's
// sample sits at k + 0.5 + j. Clamped to the layer.
ivec2 layer_texel(LayerInfo l, vec2 j, vec2 pc) {
    vec2 t = (pc + fovea_frame.jitter_px - l.a.xy) / l.a.z - j;
    return clamp(ivec2(floor(t)), ivec2(0), ivec2(l.b.xy) - 1);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ivec2(fovea_frame.extent)))) return;
    vec2 pc = vec2(p) + 0.5;
    // Outer layer first, then every inner layer that covers the pixel overrides it.
    LayerInfo lo = table.layer[LAYERS - 1];
    ivec2 t = layer_texel(lo, dp.jitter[LAYERS - 1].xy, pc);
    float depth = imageLoad(depth_outer, t).x;
    vec2 flow = (imageLoad(motion_outer, t).xy + dp.jitter[LAYERS - 1].xy) * lo.a.z;
    LayerInfo l2 = table.layer[2];
    if (LAYERS > 3 && layers_mask(length(pc - l2.c.xy), l2.b.z) >= 0.5) {
        t = layer_texel(l2, dp.jitter[2].xy, pc);
        depth = imageLoad(depth2, t).x;
        flow = (imageLoad(motion2, t).xy + dp.jitter[2].xy) * l2.a.z;
    }
    LayerInfo l1 = table.layer[1];
    if (LAYERS > 2 && layers_mask(length(pc - l1.c.xy), l1.b.z) >= 0.5) {
        t = layer_texel(l1, dp.jitter[1].xy, pc);
        depth = imageLoad(depth1, t).x;
        flow = (imageLoad(motion1, t).xy + dp.jitter[1].xy) * l1.a.z;
    }
    LayerInfo l0 = table.layer[0];
    if (layers_mask(length(pc - l0.c.xy), l0.b.z) >= 0.5) {
        t = layer_texel(l0, dp.jitter[0].xy, pc);
        depth = imageLoad(depth0, t).x;
        flow = (imageLoad(motion0, t).xy + dp.jitter[0].xy) * l0.a.z;
    }
    imageStore(out_depth, p, vec4(depth));
    imageStore(out_motion, p, vec4(flow - fovea_frame.jitter_px, 0.0, 0.0));
}
