// The per-view uniform block of the viewer's raster passes (a dynamic offset per view: the full
// frame or one of the module's views), and the previous frame's position for motion vectors.
#ifndef VIEWER_VIEW_GLSL
#define VIEWER_VIEW_GLSL

layout(std140, set = 0, binding = 0) uniform ViewerView {
    mat4 view_proj;       // jittered, cropped (fovea::vk::crop_projection)
    mat4 prev_view_proj;  // previous frame, cropped, unjittered
    mat4 inv_view_proj;   // of view_proj: pixel -> world ray (sky)
    vec4 eye;             // xyz camera position
    vec4 size;            // xy view pixels, zw 1 / size
    vec4 scale;           // x output (full-frame) pixels per view pixel: 1, or a layer's s
} viewer_view;

layout(push_constant) uniform ViewerDraw {
    mat4 model;
    vec4 normal_matrix[3];  // inverse transpose of model's 3x3, columns; [0].w = det sign
    int material;
    int pad0, pad1, pad2;
} viewer_draw;

// Motion in this view's pixels, current - previous, from the unjittered pixel centre
// (gl_FragCoord) to where the world point was last frame (fovea/vk/projection.hpp).
vec2 viewer_motion(vec4 frag_coord, vec4 prev_clip) {
    if (prev_clip.w <= 1e-6) return vec2(0.0);
    vec2 prev_px = (prev_clip.xy / prev_clip.w * 0.5 + 0.5) * viewer_view.size.xy;
    return frag_coord.xy - prev_px;
}

#endif
