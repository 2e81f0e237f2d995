#version 450
// Guenter 2012: shade one eccentricity layer from the G-buffer the host rendered for its crop
// (ViewRequest), one shade per layer texel with a footprint of s display pixels.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "fovea_host.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
// The layer's G-buffer, as fovea_frame.glsl's set 0 bindings 1-4 (gbuffer.hpp), then its colour.
layout(set = 1, binding = 0, rgba32f) uniform readonly image2D l_position;
layout(set = 1, binding = 1, rgba32ui) uniform readonly uimage2D l_surface;
layout(set = 1, binding = 2, r32f) uniform readonly image2D l_depth;
layout(set = 1, binding = 3, rg16f) uniform readonly image2D l_motion;
layout(set = 1, binding = 4, rgba16f) uniform writeonly image2D l_color;

layout(push_constant) uniform ShadePush {
    vec2 origin;   // full-resolution pixel of the layer's top-left corner
    vec2 jitter;   // this frame's jitter in layer texels
    float s;       // sampling factor: display pixels per layer texel
    float pad0, pad1, pad2;
} sp;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(l_color);
    if (gl_LocalInvocationIndex == 0u) {
        // Each workgroup counts its in-bounds texels once (no shared-memory barrier).
        ivec2 n = clamp(size - ivec2(gl_WorkGroupID.xy) * 8, ivec2(0), ivec2(8));
        atomicAdd(fovea_stats.shaded_samples, uint(n.x * n.y));
    }
    if (all(lessThan(t, size))) {
        FoveaGSample g = fovea_decode_gsample(imageLoad(l_position, t), imageLoad(l_surface, t),
                                              imageLoad(l_depth, t).x, imageLoad(l_motion, t).xy);
        vec2 centre = sp.origin + (vec2(t) + 0.5 + sp.jitter) * sp.s;
        float s_t = clamp(log2(sp.s) * 0.5, 0.0, 1.0);
        vec3 c = fovea_shade(g, fovea_make_footprint(centre, sp.s, g.distance, s_t));
        // Keep samples finite: upsampling and history blends mix with zero weights (0 · inf).
        c = min(mix(c, vec3(0.0), isnan(c)), vec3(65504.0));
        imageStore(l_color, t, vec4(c, 1.0));
    }
}
