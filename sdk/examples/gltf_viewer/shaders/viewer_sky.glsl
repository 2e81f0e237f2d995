// The sky pixel's world direction (through the jittered pixel centre, as the geometry samples)
// and its motion from the camera's rotation (a direction at infinity).
#ifndef VIEWER_SKY_GLSL
#define VIEWER_SKY_GLSL

vec3 viewer_sky_direction(vec2 frag) {
    vec2 ndc = frag * viewer_view.size.zw * 2.0 - 1.0;
    vec4 far = viewer_view.inv_view_proj * vec4(ndc, 1.0, 1.0);
    vec4 near = viewer_view.inv_view_proj * vec4(ndc, 0.0, 1.0);
    return normalize(far.xyz / far.w - near.xyz / near.w);
}

vec2 viewer_sky_motion(vec4 frag_coord, vec3 dir) {
    return viewer_motion(frag_coord, viewer_view.prev_view_proj * vec4(dir, 0.0));
}

#endif
