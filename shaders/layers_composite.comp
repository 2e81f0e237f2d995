#version 450
// Guenter 2012 Fig. 3: every display pixel bilinearly upsamples each layer's resolved image and
// blends from the outer layer inwards with smoothstep circle masks (transition 40 % of the
// layer radius). The outer layer covers the whole display, so no pixel is ever left uncovered.
#extension GL_GOOGLE_include_directive : require
#include "fovea_frame.glsl"
#include "layers_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
// Two history images per layer (ping-pong); LayerInfo.a.w says which one is current.
layout(set = 1, binding = 0, rgba16f) uniform readonly image2D h0a;
layout(set = 1, binding = 1, rgba16f) uniform readonly image2D h0b;
layout(set = 1, binding = 2, rgba16f) uniform readonly image2D h1a;
layout(set = 1, binding = 3, rgba16f) uniform readonly image2D h1b;
layout(set = 1, binding = 4, rgba16f) uniform readonly image2D h2a;
layout(set = 1, binding = 5, rgba16f) uniform readonly image2D h2b;
layout(set = 1, binding = 6, rgba16f) uniform readonly image2D h3a;
layout(set = 1, binding = 7, rgba16f) uniform readonly image2D h3b;
layout(std430, set = 1, binding = 8) readonly buffer LayerTable {
    int count;
    int pad0, pad1, pad2;
    LayerInfo layer[4];
} table;

vec4 load_layer(int i, int which, ivec2 t) {
    if (i == 0) return which == 0 ? imageLoad(h0a, t) : imageLoad(h0b, t);
    if (i == 1) return which == 0 ? imageLoad(h1a, t) : imageLoad(h1b, t);
    if (i == 2) return which == 0 ? imageLoad(h2a, t) : imageLoad(h2b, t);
    return which == 0 ? imageLoad(h3a, t) : imageLoad(h3b, t);
}

vec3 sample_layer(int i, vec2 pixel_centre) {
    LayerInfo l = table.layer[i];
    ivec2 size = ivec2(l.b.xy);
    int which = int(l.a.w);
    vec2 f = (pixel_centre - l.a.xy) / l.a.z - 0.5;
    ivec2 b = ivec2(floor(f));
    vec2 w = f - vec2(b);
    ivec2 hi = size - 1;
    vec3 c00 = load_layer(i, which, clamp(b, ivec2(0), hi)).rgb;
    vec3 c10 = load_layer(i, which, clamp(b + ivec2(1, 0), ivec2(0), hi)).rgb;
    vec3 c01 = load_layer(i, which, clamp(b + ivec2(0, 1), ivec2(0), hi)).rgb;
    vec3 c11 = load_layer(i, which, clamp(b + ivec2(1, 1), ivec2(0), hi)).rgb;
    return mix(mix(c00, c10, w.x), mix(c01, c11, w.x), w.y);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, ivec2(fovea_frame.extent)))) return;
    vec2 pc = vec2(p) + 0.5;
    int n = table.count;
    vec3 c = sample_layer(n - 1, pc);
    float s = table.layer[n - 1].a.z;
    for (int i = n - 2; i >= 0; --i) {
        LayerInfo l = table.layer[i];
        vec2 centre = l.a.xy + 0.5 * l.b.xy * l.a.z;
        float w = layers_mask(length(pc - centre), l.b.z);
        if (w > 0.0) {
            c = mix(c, sample_layer(i, pc), w);
            if (w >= 0.5) s = l.a.z;
        }
    }
    imageStore(fovea_out_color, p, vec4(c, 1.0));
    imageStore(fovea_out_rate, p, vec4(clamp(log2(s) * 0.5, 0.0, 1.0)));
}
