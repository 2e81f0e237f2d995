#version 450
// The G-buffer pass (path 1): the module's packed G-buffer (fovea/vk/gbuffer.hpp) for the full
// frame or a layer view. Textures are sampled again by fovea_shade() at the footprint's LOD
// (viewer_shade.glsl), so the surface carries what that needs: material id, the texture
// coordinates and this pixel's texture LOD; albedo is the base colour at the hardware LOD (the
// module's adaptive method compares it across pixels).
#extension GL_GOOGLE_include_directive : require
#include "viewer_view.glsl"
#include "viewer_scene.glsl"
#include "viewer_pbr.glsl"
#include "viewer_surface.glsl"
#include "viewer_gbuffer.glsl"
#include "fovea_gbuffer.glsl"

layout(location = 0) out vec4 out_position;
layout(location = 1) out uvec4 out_surface;
layout(location = 2) out float out_depth;
layout(location = 3) out vec2 out_motion;

void main() {
    float alpha;
    ViewerSurface s = viewer_fragment_surface(alpha);
    float cutoff = viewer_materials[viewer_draw.material].alpha_cutoff;
    if (cutoff >= 0.0 && alpha < cutoff) discard;
    // LOD per output pixel: a layer texel spans scale.x of them, fovea_shade adds its footprint.
    float lod = textureQueryLod(viewer_color_textures, in_uv).y - log2(viewer_view.scale.x);
    out_position = vec4(in_world, max(distance(in_world, viewer_view.eye.xyz), 1e-6));
    out_surface = fovea_pack_surface(s.normal, s.base_color, 1.0,
                                     viewer_pack_material(viewer_draw.material, lod, in_uv));
    out_depth = gl_FragCoord.z;
    out_motion = viewer_motion(gl_FragCoord, in_prev_clip);
}
