#version 450
// Build-time check of a host's shading function: fovea_check_shading() (foveaConfig.cmake)
// compiles this with the host's GLSL as fovea_host.glsl, against the same frame contract every
// shading pass of the module includes, so a host learns of an error when it builds, not when
// Foveator::create() compiles its pipelines. Define FOVEA_CHECK_BACKGROUND to check
// fovea_background() too. Not a pass of the module.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "fovea_host.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ivec2(fovea_frame.extent)))) return;
    FoveaGSample g = fovea_load_gsample(p);
    FoveaFootprint fp = fovea_make_footprint(vec2(p) + 0.5, 1.0, g.distance, 0.0);
    vec3 c = fovea_shade(g, fp);
#ifdef FOVEA_CHECK_BACKGROUND
    if (g.background) c = fovea_background(g, fp);
#endif
    imageStore(fovea_out_color, p, vec4(c, 1.0));
}
