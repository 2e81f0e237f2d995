#version 450
// Path 3 with VK_EXT_fragment_density_map: the acuity model's tile rate as a density per axis,
// floor(255 / rate) / 255 (the fragment area 1 / density is then never below the rate). One
// thread per texel; push constants as shaders/vrs_rate.comp.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "fovea_acuity.glsl"
layout(set = 0, binding = 0, rg8) uniform writeonly image2D density_image;
layout(push_constant) uniform RatePush {
    FoveaDisplay display;
    FoveaAcuity acuity;
    vec2 gaze_px;
    vec2 texel;  // texel size in pixels
} rp;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(density_image)))) return;
    vec2 lo = vec2(t) * rp.texel;
    vec2 hi = min(lo + rp.texel, rp.display.size_px);
    float r = fovea_tile_rate(rp.display, rp.acuity, lo, hi, rp.gaze_px);
    imageStore(density_image, t, vec4(vec2(floor(255.0 / r) / 255.0), 0.0, 0.0));
}
