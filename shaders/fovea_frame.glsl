// The frame descriptor set (set 0) every shading pipeline sees, the G-buffer sample and the
// shading footprint handed to the host's shading function. Mirrors sdk/src/vk/frame_uniforms.hpp
// (std140) and the G-buffer contract in sdk/include/fovea/vk/gbuffer.hpp.
#ifndef FOVEA_FRAME_GLSL
#define FOVEA_FRAME_GLSL

#include "fovea_acuity.glsl"
#include "fovea_gbuffer.glsl"

// The host's own descriptor set (FoveatorConfig::host_set_layout, FrameInputs::host_set): a
// shading function declares its resources as layout(set = FOVEA_HOST_SET, binding = n).
#define FOVEA_HOST_SET 2

layout(std140, set = 0, binding = 0) uniform FoveaFrameUniforms {
    vec2 extent;          // output size in pixels
    vec2 inv_extent;
    vec2 gaze_px;         // resolved gaze centre (landing point during saccades), pixels
    vec2 jitter_px;       // this frame's sub-pixel jitter the host applied to its projection
    FoveaDisplay display;
    FoveaAcuity acuity;
    vec4 camera_pos;      // xyz world eye position, w = radians per pixel at the view centre
    vec4 time;            // x seconds, y frame index, z method id (host free), w reserved
    vec4 host[16];        // host-defined parameters (Foveator::set_host_params)
} fovea_frame;

// G-buffer (read by the module, written by the host), all VK_IMAGE_LAYOUT_GENERAL.
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D fovea_g_position;  // xyz world, w view distance (0 = background)
layout(set = 0, binding = 2, rgba32ui) uniform readonly uimage2D fovea_g_surface; // normal, albedo, material (fovea_gbuffer.glsl)
layout(set = 0, binding = 3, r32f) uniform readonly image2D fovea_g_depth;        // 0..1, 1 = far/background
layout(set = 0, binding = 4, rg16f) uniform readonly image2D fovea_g_motion;      // pixels, current - previous

// Outputs of the shading stage.
layout(set = 0, binding = 5, rgba16f) uniform writeonly image2D fovea_out_color;  // linear HDR rgb, a = 1
layout(set = 0, binding = 6, r16f) uniform writeonly image2D fovea_out_rate;      // S_t (0 fovea .. 1 coarsest)

// Counters read back after each frame (sdk/src/vk/frame_uniforms.hpp FrameStats).
layout(std430, set = 0, binding = 7) buffer FoveaStats {
    uint shaded_samples;  // every method adds the samples it shaded
    uint edge_samples;    // of which: extra samples at coarse-pixel discontinuities
    uint tiles[4];        // tiles per rate class (1x1, 2x2, 4x4, skipped)
    uint background_tiles;  // of tiles[3]: environment only (cps: fovea_background)
    uint reused_tiles;      // of tiles[3]: last frame's shading kept (cps: still and converged)
    uint flat_tiles;        // shaded coarser than acuity: flat or saturated last frame
    uint no_detail_tiles;   // flagged "no detail to extend" (background, flat, saturated)
    uint reserved[6];
} fovea_stats;

struct FoveaGSample {
    vec3 position;   // world
    float distance;  // view distance, 0 = background (no geometry)
    vec3 normal;     // unit
    vec3 albedo;
    float albedo_a;
    vec4 material;   // x = material id (an integer), yzw host-defined (stored as halves)
    float depth;
    vec2 motion;
    bool background;
};

// What the shade stands for: the host pre-filters over size_px full-resolution pixels.
struct FoveaFootprint {
    vec2 pixel;             // centre of the shaded region, full-resolution pixel coordinates
    float size_px;          // edge of the region in pixels (1, 2, 4, ...)
    float world_size;       // approximate world-space edge of the region at the sample
    float eccentricity_deg; // from the gaze
    float rate_s;           // normalized shading rate S_t of the region
};

// A sample from its G-buffer texels (the full-resolution images here, a layer's in layers_shade).
FoveaGSample fovea_decode_gsample(vec4 pos, uvec4 surface, float depth, vec2 motion) {
    FoveaGSample g;
    g.position = pos.xyz;
    g.distance = pos.w;
    g.normal = fovea_unpack_normal(surface);
    vec4 alb = fovea_unpack_albedo(surface);
    g.albedo = alb.rgb;
    g.albedo_a = alb.a;
    g.material = fovea_unpack_material(surface);
    g.depth = depth;
    g.motion = motion;
    g.background = !(pos.w > 0.0);
    return g;
}

// Loads the shader does not use (depth, motion, most often) are dropped by the compiler.
FoveaGSample fovea_load_gsample(ivec2 p) {
    return fovea_decode_gsample(imageLoad(fovea_g_position, p), imageLoad(fovea_g_surface, p),
                                imageLoad(fovea_g_depth, p).x, imageLoad(fovea_g_motion, p).xy);
}

FoveaFootprint fovea_make_footprint(vec2 centre_px, float size_px, float distance, float rate_s) {
    FoveaFootprint f;
    f.pixel = centre_px;
    f.size_px = size_px;
    f.world_size = size_px * fovea_frame.camera_pos.w * max(distance, 0.0);
    f.eccentricity_deg = fovea_eccentricity_deg(fovea_frame.display, centre_px, fovea_frame.gaze_px);
    f.rate_s = rate_s;
    return f;
}

#endif
