// Build-time stand-in for the host's shading function. At run time the module's glslang includer
// serves the host's GLSL (FoveatorConfig::shading_glsl) under this name instead.
//
// The contract (see sdk/include/fovea/vk/foveator.hpp): define
//     vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp);
// returning linear HDR radiance for the G-buffer sample g, pre-filtered over fp.size_px pixels
// (fp.world_size world units). It may read fovea_frame (camera, time, host[16]) and must not
// write any image. It is called for background samples too (g.background).
vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) {
    if (g.background) return vec3(0.0);
    return g.albedo * max(dot(g.normal, normalize(vec3(0.3, 0.8, 0.5))), 0.0) + 0.0 * fp.size_px;
}
