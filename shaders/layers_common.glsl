// Guenter et al. 2012 eccentricity layers: the per-layer table shared by the resolve and
// composite passes (sdk/src/vk/methods/layers.cpp LayerTable) and bilinear helpers.
#ifndef LAYERS_COMMON_GLSL
#define LAYERS_COMMON_GLSL

struct LayerInfo {
    vec4 a;  // origin.xy (full-resolution pixels of the layer's top-left corner), s, unused
    vec4 b;  // size in layer texels (w, h), mask radius in pixels (0: the outer layer), unused
    vec4 c;  // mask centre (the gaze the layer was rendered for), pixels; zw unused
};

// Smoothstep blend of an inner layer (Fig. 3): weight 1 inside 60 % of its radius, 0 at the
// radius; the transition is 40 % of the radius.
float layers_mask(float d, float radius) {
    return 1.0 - smoothstep(0.6 * radius, radius, d);
}

#endif
