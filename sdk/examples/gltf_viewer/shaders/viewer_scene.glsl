// The viewer's scene resources, one descriptor set shared by its raster passes (set 1) and, as
// the module's host set (FOVEA_HOST_SET), by its fovea_shade(): lights and environment,
// materials, and every texture as one layer of a mipmapped array (all resampled to one size at
// load, so a per-pixel material needs no descriptor indexing; every texture repeats, glTF's
// default wrap mode). Mirrors src/renderer.cpp.
#ifndef VIEWER_SCENE_GLSL
#define VIEWER_SCENE_GLSL

#ifndef VIEWER_SCENE_SET
#define VIEWER_SCENE_SET 1
#endif

struct ViewerLight {
    vec4 position;  // xyz direction the light travels (w = 0) or position (w = 1)
    vec4 color;     // rgb * intensity
};

layout(std140, set = VIEWER_SCENE_SET, binding = 0) uniform ViewerScene {
    ViewerLight lights[8];
    vec4 sky;      // rgb, w = environment intensity
    vec4 horizon;
    vec4 ground;
    ivec4 counts;  // x lights, y texture layers, z texture size (texels)
} viewer_scene;

struct ViewerMaterial {
    vec4 base_color;
    vec3 emissive;
    float metallic;
    float roughness;
    float normal_scale;
    float occlusion_strength;
    float alpha_cutoff;  // < 0: opaque
    int base_tex, mr_tex, normal_tex, occlusion_tex;
    int emissive_tex;
    float f0;
    float pad0, pad1;
};

layout(std430, set = VIEWER_SCENE_SET, binding = 1) readonly buffer ViewerMaterials {
    ViewerMaterial viewer_materials[];
};

// Base colour and emissive textures (sRGB, decoded to linear on read) and the data textures
// (metallic-roughness, normal, occlusion), each material index a layer of its array.
layout(set = VIEWER_SCENE_SET, binding = 2) uniform sampler2DArray viewer_color_textures;
layout(set = VIEWER_SCENE_SET, binding = 3) uniform sampler2DArray viewer_data_textures;

// Hardware-derivative samples (raster passes) and explicit LODs (the module's compute shading).
vec4 viewer_color_tex(int layer, vec2 uv) {
    return texture(viewer_color_textures, vec3(uv, float(layer)));
}
vec4 viewer_data_tex(int layer, vec2 uv) {
    return texture(viewer_data_textures, vec3(uv, float(layer)));
}
vec4 viewer_color_tex_lod(int layer, vec2 uv, float lod) {
    return textureLod(viewer_color_textures, vec3(uv, float(layer)), lod);
}
vec4 viewer_data_tex_lod(int layer, vec2 uv, float lod) {
    return textureLod(viewer_data_textures, vec3(uv, float(layer)), lod);
}

#endif
