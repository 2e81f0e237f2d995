#version 450
#extension GL_GOOGLE_include_directive : require
// Enhancement pass 1: display-referred luminance (after tone map and gamma), level 0 of the
// Gaussian pyramid.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D luma_out;

#include "enhance_common.glsl"

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(color_in)))) return;
    vec3 c = imageLoad(color_in, p).rgb;
    vec3 d = vec3(enh_display_encode(c.r), enh_display_encode(c.g), enh_display_encode(c.b));
    imageStore(luma_out, p, vec4(clamp(enh_luma(d), 0.0, 1.0)));
}
