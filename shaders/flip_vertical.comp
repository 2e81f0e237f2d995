#version 450
// LDR-FLIP step 3: every column filtered at its rows' ppd, then per pixel the colour difference
// (filtered YCxCz -> linear RGB clamped to [0, 1] -> Hunt-adjusted L*a*b* -> HyAB^qc,
// redistributed) and the feature difference (edge and point magnitudes). mode 0 keeps this
// image's filtered values as the reference; mode 1 writes FLIP against that reference (NaN where
// the reference pixel is invalid).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;

#include "flip_common.glsl"
#define FLIP_COLOUR_BINDING 6
#include "flip_colour.glsl"

// Reads through texel buffers, as in flip_horizontal.comp.
layout(set = 0, binding = 0) uniform samplerBuffer horizontal;  // flip_horizontal.comp's planes
// Per reference two planes: (L, a, b, edge), then (point, valid, 0, 0). Written through storage
// texel buffers (one 16-byte store per lane on llvmpipe), read through reference_in.
layout(set = 0, binding = 1, rgba32f) uniform writeonly imageBuffer reference;
layout(set = 0, binding = 2, r32f) uniform writeonly imageBuffer map;
layout(set = 0, binding = 3) uniform usamplerBuffer axes;
layout(set = 0, binding = 4) uniform samplerBuffer weights;
layout(set = 0, binding = 5) uniform usamplerBuffer block_axis;
layout(set = 0, binding = 7) uniform samplerBuffer reference_in;  // Reference, to read

// One pipeline per mode (llvmpipe would run both under a lane mask).
layout(constant_id = 0) const uint mode = 0u;  // 0: store as reference, 1: compare with it

layout(push_constant) uniform Push {
    uvec2 size;
    uint blocks_x;
    uint block_offset;  // this ppd field's first column block in block_axis (rows follow)
    uint reference_offset;  // this reference's first texel in reference
};

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, size))) return;
    FlipAxis column = flip_axis(axes, block_axis, block_offset + gl_WorkGroupID.x);
    FlipAxis a = flip_axis(axes, block_axis, block_offset + blocks_x + gl_WorkGroupID.y);
    int last = int(size.y) - 1;
    // Even kernels (the derivative odd), paired as in flip_horizontal.comp.
    int rc = a.colour_radius, rf = a.feature_radius;
    uint here = p.y * size.x + p.x, plane = size.x * size.y;
    vec4 h0 = texelFetch(horizontal, int(here));
    vec4 w0 = texelFetch(weights, int(a.colour_offset) + rc);
    vec3 c = vec3(w0.x * h0.x, w0.y * h0.y, w0.z * h0.z + w0.w * h0.w);
    for (int j = 1; j <= rc; ++j) {
        uint up = uint(max(int(p.y) - j, 0)) * size.x + p.x;
        uint down = uint(min(int(p.y) + j, last)) * size.x + p.x;
        vec4 h = texelFetch(horizontal, int(up)) + texelFetch(horizontal, int(down));
        vec4 w = texelFetch(weights, int(a.colour_offset) + rc + j);
        c += vec3(w.x * h.x, w.y * h.y, w.z * h.z + w.w * h.w);
    }
    c.z /= column.cz1_sum * a.cz1_sum + column.cz2_sum * a.cz2_sum;
    vec4 f0 = texelFetch(horizontal, int(plane + here));
    vec3 v0 = texelFetch(weights, int(a.feature_offset) + rf).xyz;
    vec4 d = vec4(v0.x * f0.y, v0.x * f0.z, v0.y * f0.x, v0.z * f0.x);  // dx, ddx, dy, ddy
    for (int j = 1; j <= rf; ++j) {
        uint up = plane + uint(max(int(p.y) - j, 0)) * size.x + p.x;
        uint down = plane + uint(min(int(p.y) + j, last)) * size.x + p.x;
        vec4 hu = texelFetch(horizontal, int(up)), hd = texelFetch(horizontal, int(down));
        vec4 sum = hu + hd;
        vec3 w = texelFetch(weights, int(a.feature_offset) + rf + j).xyz;
        d += vec4(w.x * sum.y, w.x * sum.z, w.y * (hd.x - hu.x), w.z * sum.x);
    }
    vec3 lab = flip_linear_rgb_to_hunt_lab(clamp(flip_ycxcz_to_linear_rgb(c), 0.0, 1.0));
    float edge = length(d.xz), point = length(d.yw);
    uint r = reference_offset + here;
    float valid = f0.w;
    if (mode == 0u) {
        imageStore(reference, int(r), vec4(lab, edge));
        imageStore(reference, int(r + plane), vec4(point, valid, 0.0, 0.0));
        return;
    }
    vec4 r0 = texelFetch(reference_in, int(r)), r1 = texelFetch(reference_in, int(r + plane));
    if (r1.y == 0.0) {
        imageStore(map, int(here), vec4(uintBitsToFloat(0x7fc00000u)));  // NaN: not pooled
        return;
    }
    float hyab = abs(r0.x - lab.x) + length(r0.yz - lab.yz);
    float cmax = flip_colour.colour.x, knee = flip_colour.colour.y, pt = flip_colour.colour.z;
    float e = hyab > 0.0 ? pow(hyab, flip_colour.colour.w) : 0.0;
    float colour = e < knee ? e * pt / knee : pt + (e - knee) / (cmax - knee) * (1.0 - pt);
    float feature = sqrt(max(abs(r0.w - edge), abs(r1.x - point)) * flip_colour.feature.x);
    float exponent = 1.0 - feature;
    // pow(0, y) is undefined in GLSL for y <= 0; the reference's is 0 for y > 0 and 1 at 0.
    float flip = colour > 0.0 ? pow(colour, exponent) : (exponent > 0.0 ? 0.0 : 1.0);
    imageStore(map, int(here), vec4(flip));
}
