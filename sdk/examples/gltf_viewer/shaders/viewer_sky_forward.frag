#version 450
#extension GL_GOOGLE_include_directive : require
#include "viewer_view.glsl"
#include "viewer_scene.glsl"
#include "viewer_pbr.glsl"
#include "viewer_sky.glsl"

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_depth;
layout(location = 2) out vec2 out_motion;

void main() {
    vec3 d = viewer_sky_direction(gl_FragCoord.xy);
    out_color = vec4(viewer_environment(d), 1.0);
    out_depth = 1.0;
    out_motion = viewer_sky_motion(gl_FragCoord, d);
}
