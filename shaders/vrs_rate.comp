#version 450
// The hardware VRS path: the acuity model's tile rate written into a fragment-shading-rate
// attachment texel, (log2 w << 2) | log2 h. One thread per texel.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "fovea_acuity.glsl"
layout(set = 0, binding = 0, r8ui) uniform writeonly uimage2D vrs_image;
layout(push_constant) uniform VrsPush {
    FoveaDisplay display;
    FoveaAcuity acuity;
    vec2 gaze_px;
    vec2 texel;  // texel size in pixels
} vrs;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, imageSize(vrs_image)))) return;
    vec2 lo = vec2(t) * vrs.texel;
    vec2 hi = min(lo + vrs.texel, vrs.display.size_px);
    float r = fovea_tile_rate(vrs.display, vrs.acuity, lo, hi, vrs.gaze_px);
    imageStore(vrs_image, t, uvec4(fovea_vrs_encode(r)));
}
