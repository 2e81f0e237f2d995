// What the viewer keeps in the G-buffer's host-defined material fields (fovea_gbuffer.glsl:
// x an integer id, yzw halves): x the material index, y the texture LOD of the pixel at full
// rate, zw the texture coordinates folded into one repeat (every texture repeats), centred on 0
// where halves are finest (2^-12: a quarter texel of a 1024^2 texture).
#ifndef VIEWER_GBUFFER_GLSL
#define VIEWER_GBUFFER_GLSL

vec4 viewer_pack_material(int material, float lod, vec2 uv) {
    return vec4(float(material), clamp(lod, -16.0, 16.0), fract(uv) - 0.5);
}
int viewer_material_id(vec4 m) { return int(m.x + 0.5); }
float viewer_material_lod(vec4 m) { return m.y; }
vec2 viewer_material_uv(vec4 m) { return m.zw + 0.5; }

#endif
