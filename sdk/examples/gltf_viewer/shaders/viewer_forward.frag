#version 450
// The forward pass (paths 2 and 4, and their full-rate reference): the viewer's own shading
// into the module's colour, depth and motion (fovea::vk::HostTargets formats).
#extension GL_GOOGLE_include_directive : require
#include "viewer_view.glsl"
#include "viewer_scene.glsl"
#include "viewer_pbr.glsl"
#include "viewer_surface.glsl"

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_depth;
layout(location = 2) out vec2 out_motion;

void main() {
    float alpha;
    ViewerSurface s = viewer_fragment_surface(alpha);
    float cutoff = viewer_materials[viewer_draw.material].alpha_cutoff;
    if (cutoff >= 0.0 && alpha < cutoff) discard;
    out_color = vec4(viewer_shade_surface(s, viewer_view.eye.xyz), 1.0);
    out_depth = gl_FragCoord.z;
    out_motion = viewer_motion(gl_FragCoord, in_prev_clip);
}
