// The deferred path's shading function (FoveatorConfig::shading_glsl; src/renderer.cpp joins
// viewer_scene.glsl, viewer_pbr.glsl, viewer_gbuffer.glsl and this file, with the scene set as
// the module's host set). The same glTF BRDF as the forward pass, with every texture read again
// at the pixel's LOD plus log2 of the footprint, so a coarse pixel's shade is the texture's
// average over the pixels it stands for (Patney 2016), and Toksvig's roughness from the
// normal map's average over that footprint keeps coarse highlights from aliasing.

vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) {
    if (g.background) return viewer_environment(g.normal);
    ViewerMaterial m = viewer_materials[viewer_material_id(g.material)];
    vec2 uv = viewer_material_uv(g.material);
    float lod = viewer_material_lod(g.material) + log2(max(fp.size_px, 1.0));
    ViewerSurface s;
    s.position = g.position;
    s.normal = g.normal;
    vec4 base = m.base_color;
    if (m.base_tex >= 0) base *= viewer_color_tex_lod(m.base_tex, uv, lod);
    s.base_color = base.rgb;
    vec2 mr = vec2(m.roughness, m.metallic);
    if (m.mr_tex >= 0) mr *= viewer_data_tex_lod(m.mr_tex, uv, lod).gb;
    s.roughness = clamp(mr.x, 0.03, 1.0);
    s.metallic = clamp(mr.y, 0.0, 1.0);
    if (m.normal_tex >= 0) {
        // A mip level averages unit normals: its length says how much they spread.
        vec3 tn = viewer_data_tex_lod(m.normal_tex, uv, lod).xyz * 2.0 - 1.0;
        s.roughness = viewer_toksvig_roughness(s.roughness, length(tn));
    }
    s.occlusion = 1.0;
    if (m.occlusion_tex >= 0)
        s.occlusion =
            1.0 + m.occlusion_strength * (viewer_data_tex_lod(m.occlusion_tex, uv, lod).r - 1.0);
    s.emissive = m.emissive;
    if (m.emissive_tex >= 0) s.emissive *= viewer_color_tex_lod(m.emissive_tex, uv, lod).rgb;
    s.f0 = m.f0;
    return viewer_shade_surface(s, fovea_frame.camera_pos.xyz);
}
