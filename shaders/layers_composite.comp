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
// Inner layers 0..LAYERS-2 at bindings 0..2, the outer layer always at binding 3. The inner
// layer is read texel by texel, the coarser ones through the bilinear sampler.
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D layer0;
layout(set = 1, binding = 1) uniform sampler2D layer1;
layout(set = 1, binding = 2) uniform sampler2D layer2;
layout(set = 1, binding = 3) uniform sampler2D outer_layer;
layout(std430, set = 1, binding = 4) readonly buffer LayerTable {
    int count;
    int pad0, pad1, pad2;
    LayerInfo layer[4];
} table;

// Bilinear lookup of layer `l` for a display pixel: texel k covers display pixels
// origin + [k, k + 1) * s. The coarse layers are resolved onto their unjittered grids; the
// pixel's sample sits at its centre plus the frame's jitter, as in the inner layer and the
// full-rate frame (and as TAA expects), so the layers are read there: read at the bare centre
// they sat up to half a pixel off the fovea, moving every frame.
vec3 layer_sample(sampler2D img, LayerInfo l, vec2 pixel_centre) {
    vec2 sample_px = pixel_centre + fovea_frame.jitter_px;
    return textureLod(img, (sample_px - l.a.xy) / (l.a.z * l.b.xy), 0.0).rgb;
}

float layer_weight(LayerInfo l, vec2 pc) {
    return layers_mask(length(pc - l.c.xy), l.b.z);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ivec2(fovea_frame.extent)))) return;
    vec2 pc = vec2(p) + 0.5;
    LayerInfo lo = table.layer[LAYERS - 1];
    vec3 c = layer_sample(outer_layer, lo, pc);
    float s = lo.a.z;
    if (LAYERS > 3) {
        float w = layer_weight(table.layer[2], pc);
        c = mix(c, layer_sample(layer2, table.layer[2], pc), w);
        s = w >= 0.5 ? table.layer[2].a.z : s;
    }
    if (LAYERS > 2) {
        float w = layer_weight(table.layer[1], pc);
        c = mix(c, layer_sample(layer1, table.layer[1], pc), w);
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
