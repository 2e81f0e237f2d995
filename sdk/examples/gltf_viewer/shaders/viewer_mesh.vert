#version 450
// Every glTF primitive of the viewer, in the full frame or a module view (ViewerView).
#extension GL_GOOGLE_include_directive : require
#include "viewer_view.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec4 out_tangent;
layout(location = 3) out vec2 out_uv;
layout(location = 4) out vec4 out_prev_clip;

void main() {
    vec4 w = viewer_draw.model * vec4(in_position, 1.0);
    mat3 nm = mat3(viewer_draw.normal_matrix[0].xyz, viewer_draw.normal_matrix[1].xyz,
                   viewer_draw.normal_matrix[2].xyz);
    out_world = w.xyz;
    out_normal = nm * in_normal;
    // A mirroring transform flips the bitangent: carry its sign with the tangent's.
    out_tangent = vec4(mat3(viewer_draw.model) * in_tangent.xyz,
                       in_tangent.w * viewer_draw.normal_matrix[0].w);
    out_uv = in_uv;
    out_prev_clip = viewer_view.prev_view_proj * w;  // static scene: last frame's camera only
    gl_Position = viewer_view.view_proj * w;
}
