// A host shading function as a host writes it: checked at build time by fovea_check_shading().
vec3 fovea_background(FoveaGSample g, FoveaFootprint fp) { return vec3(0.2, 0.3, 0.5); }
vec3 fovea_shade(FoveaGSample g, FoveaFootprint fp) {
    if (g.background) return fovea_background(g, fp);
    return g.albedo * max(dot(g.normal, vec3(0.0, 1.0, 0.0)), 0.1) / fp.size_px * fp.size_px;
}
