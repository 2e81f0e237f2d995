// Wrong on purpose: fovea_shade returns the wrong type; fovea_check_shading() must fail the build.
float fovea_shade(FoveaGSample g, FoveaFootprint fp) { return g.depth + undefined_name; }
