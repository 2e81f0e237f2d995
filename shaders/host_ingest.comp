#version 450
// The host's own colour, depth and motion (HostFrameImages) copied into the module's targets at
// the start of a host-shaded frame, converted to the module's conventions: depth 0 near .. 1 far
// (reverse-Z flipped), motion in pixels current - previous. Reads through samplers (texelFetch)
// so any sampleable format serves, a depth buffer's depth aspect included. Non-finite input is
// kept out: later passes mix with zero weights (0 * inf).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D host_color;
layout(set = 0, binding = 1) uniform sampler2D host_depth;
layout(set = 0, binding = 2) uniform sampler2D host_motion;
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D out_color;
layout(set = 0, binding = 4, r32f) uniform writeonly image2D out_depth;
layout(set = 0, binding = 5, rg16f) uniform writeonly image2D out_motion;

layout(push_constant) uniform IngestPush {
    vec2 motion_scale;
    int depth_reversed;
    int has_motion;
} ip;

vec4 finite_or_zero(vec4 v) {
    bvec4 bad = bvec4(uvec4(isnan(v)) | uvec4(isinf(v)));
    return mix(v, vec4(0.0), bad);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(out_color)))) return;
    vec3 c = finite_or_zero(texelFetch(host_color, p, 0)).rgb;
    imageStore(out_color, p, vec4(min(max(c, vec3(0.0)), vec3(65504.0)), 1.0));
    float d = clamp(finite_or_zero(texelFetch(host_depth, p, 0)).r, 0.0, 1.0);
    imageStore(out_depth, p, vec4(ip.depth_reversed != 0 ? 1.0 - d : d));
    vec2 m = ip.has_motion != 0 ? finite_or_zero(texelFetch(host_motion, p, 0)).rg * ip.motion_scale
                                : vec2(0.0);
    imageStore(out_motion, p, vec4(clamp(m, vec2(-65504.0), vec2(65504.0)), 0.0, 0.0));
}
