#version 450
// Guenter 2012 Fig. 3: every display pixel bilinearly upsamples each layer's resolved image and
// blends from the outer layer inwards with smoothstep circle masks (transition 40 % of the
// layer radius). The outer layer covers the whole display, so no pixel is ever left uncovered.
// Straight-line code with the layer count as a specialization constant: llvmpipe executes
// both sides of every branch, so nothing here is conditional on data.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "layers_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const int LAYERS = 3;
// Inner layers 0..LAYERS-2 at bindings 0..2, the outer layer always at binding 3.
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D layer0;
layout(set = 1, binding = 1, rgba16f) uniform readonly image2D layer1;
layout(set = 1, binding = 2, rgba16f) uniform readonly image2D layer2;
layout(set = 1, binding = 3, rgba16f) uniform readonly image2D outer_layer;
layout(std430, set = 1, binding = 4) readonly buffer LayerTable {
    int count;
    int pad0, pad1, pad2;
    LayerInfo layer[4];
} table;

// Bilinear lookup of layer `l` at a display pixel centre: the four texels and the weights.
// (GLSL cannot pass a formatted image to a function, so each layer spells out its loads.)
struct Tap {
    ivec2 t00, t10, t01, t11;
    vec2 w;
};

Tap layer_tap(LayerInfo l, vec2 pixel_centre) {
    ivec2 hi = ivec2(l.b.xy) - 1;
    vec2 f = (pixel_centre - l.a.xy) / l.a.z - 0.5;
    ivec2 b = ivec2(floor(f));
    Tap t;
    t.w = f - vec2(b);
    t.t00 = clamp(b, ivec2(0), hi);
    t.t10 = clamp(b + ivec2(1, 0), ivec2(0), hi);
    t.t01 = clamp(b + ivec2(0, 1), ivec2(0), hi);
    t.t11 = clamp(b + ivec2(1, 1), ivec2(0), hi);
    return t;
}

vec3 blend(Tap t, vec4 c00, vec4 c10, vec4 c01, vec4 c11) {
    return mix(mix(c00.rgb, c10.rgb, t.w.x), mix(c01.rgb, c11.rgb, t.w.x), t.w.y);
}

#define LAYER_SAMPLE(img, tap) \
    blend(tap, imageLoad(img, tap.t00), imageLoad(img, tap.t10), imageLoad(img, tap.t01), \
          imageLoad(img, tap.t11))

float layer_weight(LayerInfo l, vec2 pc) {
    return layers_mask(length(pc - l.c.xy), l.b.z);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ivec2(fovea_frame.extent)))) return;
    vec2 pc = vec2(p) + 0.5;
    LayerInfo lo = table.layer[LAYERS - 1];
    Tap to = layer_tap(lo, pc);
    vec3 c = LAYER_SAMPLE(outer_layer, to);
    float s = lo.a.z;
    if (LAYERS > 3) {
        float w = layer_weight(table.layer[2], pc);
        Tap t2 = layer_tap(table.layer[2], pc);
        c = mix(c, LAYER_SAMPLE(layer2, t2), w);
        s = w >= 0.5 ? table.layer[2].a.z : s;
    }
    if (LAYERS > 2) {
        float w = layer_weight(table.layer[1], pc);
        Tap t1 = layer_tap(table.layer[1], pc);
        c = mix(c, LAYER_SAMPLE(layer1, t1), w);
        s = w >= 0.5 ? table.layer[1].a.z : s;
    }
    // The inner layer is at s = 1 on a crop snapped to whole pixels: each display pixel is one
    // texel, so one load replaces the bilinear tap (a quarter of the loads, and no weights).
    LayerInfo li = table.layer[0];
    float w0 = layer_weight(li, pc);
    ivec2 t0 = clamp(ivec2(floor(pc - li.a.xy)), ivec2(0), ivec2(li.b.xy) - 1);
    c = mix(c, imageLoad(layer0, t0).rgb, w0);
    s = w0 >= 0.5 ? table.layer[0].a.z : s;
    imageStore(fovea_out_color, p, vec4(c, 1.0));
    imageStore(fovea_out_rate, p, vec4(clamp(log2(s) * 0.5, 0.0, 1.0)));
}
