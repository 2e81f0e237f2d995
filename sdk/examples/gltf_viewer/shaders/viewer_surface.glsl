// The raster passes' surface of a fragment: material, textures at hardware LOD, the normal map
// in the interpolated tangent frame, alpha mask. Included by the forward and G-buffer fragments.
#ifndef VIEWER_SURFACE_GLSL
#define VIEWER_SURFACE_GLSL

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv;
layout(location = 4) in vec4 in_prev_clip;

ViewerSurface viewer_fragment_surface(out float alpha) {
    ViewerMaterial m = viewer_materials[viewer_draw.material];
    ViewerSurface s;
    s.position = in_world;
    vec4 base = m.base_color;
    if (m.base_tex >= 0) base *= viewer_color_tex(m.base_tex, in_uv);
    alpha = base.a;
    s.base_color = base.rgb;
    vec2 mr = vec2(m.roughness, m.metallic);
    if (m.mr_tex >= 0) mr *= viewer_data_tex(m.mr_tex, in_uv).gb;  // glTF: G roughness, B metal
    s.roughness = clamp(mr.x, 0.03, 1.0);
    s.metallic = clamp(mr.y, 0.0, 1.0);
    s.occlusion = 1.0;
    if (m.occlusion_tex >= 0)
        s.occlusion = 1.0 + m.occlusion_strength * (viewer_data_tex(m.occlusion_tex, in_uv).r - 1.0);
    s.emissive = m.emissive;
    if (m.emissive_tex >= 0) s.emissive *= viewer_color_tex(m.emissive_tex, in_uv).rgb;
    s.f0 = m.f0;
    vec3 n = normalize(in_normal);
    if (!gl_FrontFacing) n = -n;
    if (m.normal_tex >= 0) {
        vec3 t = in_tangent.xyz - n * dot(n, in_tangent.xyz);
        if (dot(t, t) > 1e-12) {
            t = normalize(t);
            vec3 b = cross(n, t) * (in_tangent.w < 0.0 ? -1.0 : 1.0);
            vec3 tn = viewer_data_tex(m.normal_tex, in_uv).xyz * 2.0 - 1.0;
            tn.xy *= m.normal_scale;
            n = normalize(mat3(t, b, n) * tn);
        }
    }
    s.normal = n;
    return s;
}

#endif
