#version 450
// Background of the G-buffer pass: no geometry (distance 0), the view direction as the normal
// (fovea/vk/gbuffer.hpp), far depth, the sky's rotation motion.
#extension GL_GOOGLE_include_directive : require
#include "viewer_view.glsl"
#include "viewer_sky.glsl"
#include "fovea_gbuffer.glsl"

layout(location = 0) out vec4 out_position;
layout(location = 1) out uvec4 out_surface;
layout(location = 2) out float out_depth;
layout(location = 3) out vec2 out_motion;

void main() {
    vec3 d = viewer_sky_direction(gl_FragCoord.xy);
    out_position = vec4(0.0);
    out_surface = fovea_pack_surface(d, vec3(0.0), 0.0, vec4(0.0));
    out_depth = 1.0;
    out_motion = viewer_sky_motion(gl_FragCoord, d);
}
