#version 450
// LDR-FLIP step 3: every column filtered at its rows' ppd, then per pixel the colour difference
// (filtered YCxCz -> linear RGB clamped to [0, 1] -> Hunt-adjusted L*a*b* -> HyAB^qc,
// redistributed) and the feature difference (edge and point magnitudes). mode 0 keeps this
// image's filtered values as the reference; mode 1 writes FLIP against that reference (NaN where
// the reference pixel is invalid).
#extension GL_GOOGLE_include_directive : require
// Two rows per invocation: the lower pixel's taps are the upper's one row down, so every fetch of
// the planes and of the weights serves both. The workgroup's shape is gpu_flip.cpp's (several
// 16 x 16 blocks: each lane reads its own blocks' kernels).
layout(local_size_x_id = 1, local_size_y_id = 2) in;

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

// The colour and feature differences of one pixel from its filtered values (`here`: its texel).
void resolve(uint here, vec3 c, vec4 d, float valid) {
    vec3 lab = flip_linear_rgb_to_hunt_lab(clamp(flip_ycxcz_to_linear_rgb(c), 0.0, 1.0));
    float edge = length(d.xz), point = length(d.yw);
    uint r = reference_offset + here, plane = size.x * size.y;
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

void main() {
    uvec2 p = uvec2(gl_GlobalInvocationID.x, 2u * gl_GlobalInvocationID.y);  // and p + (0, 1)
    if (any(greaterThanEqual(p, size))) return;
    FlipAxis column = flip_axis(axes, block_axis, block_offset + p.x / kFlipBlock);
    FlipAxis a = flip_axis(axes, block_axis, block_offset + blocks_x + p.y / kFlipBlock);
    int last = int(size.y) - 1, y = int(p.y);
    // Even kernels (the derivative odd), paired as in flip_horizontal.comp. Pixel 0 is row y,
    // pixel 1 row y + 1 (clamped; dropped when past the last row). At tap j pixel 0 needs rows
    // y -+ j, pixel 1 rows y + 1 -+ j: two fetches, the other two rows carried from tap j - 1.
    int rc = a.colour_radius, rf = a.feature_radius;
    uint plane = size.x * size.y;
    uint here0 = p.y * size.x + p.x, here1 = uint(min(y + 1, last)) * size.x + p.x;
    vec4 h0 = texelFetch(horizontal, int(here0)), h1 = texelFetch(horizontal, int(here1));
    vec4 w0 = texelFetch(weights, int(a.colour_offset) + rc);
    vec3 c0 = vec3(w0.x * h0.x, w0.y * h0.y, w0.z * h0.z + w0.w * h0.w);
    vec3 c1 = vec3(w0.x * h1.x, w0.y * h1.y, w0.z * h1.z + w0.w * h1.w);
    vec4 up1 = h0, down0 = h1;  // rows y + 1 - j, y + j
    for (int j = 1; j <= rc; ++j) {
        uint up = uint(max(y - j, 0)) * size.x + p.x;
        uint down = uint(min(y + 1 + j, last)) * size.x + p.x;
        vec4 up0 = texelFetch(horizontal, int(up)), down1 = texelFetch(horizontal, int(down));
        vec4 w = texelFetch(weights, int(a.colour_offset) + rc + j);
        vec4 s0 = up0 + down0, s1 = up1 + down1;
        c0 += vec3(w.x * s0.x, w.y * s0.y, w.z * s0.z + w.w * s0.w);
        c1 += vec3(w.x * s1.x, w.y * s1.y, w.z * s1.z + w.w * s1.w);
        up1 = up0;
        down0 = down1;
    }
    float cz_sum = column.cz1_sum * a.cz1_sum + column.cz2_sum * a.cz2_sum;
    c0.z /= cz_sum;
    c1.z /= cz_sum;
    vec4 f0 = texelFetch(horizontal, int(plane + here0));
    vec4 f1 = texelFetch(horizontal, int(plane + here1));
    vec3 v0 = texelFetch(weights, int(a.feature_offset) + rf).xyz;
    vec4 d0 = vec4(v0.x * f0.y, v0.x * f0.z, v0.y * f0.x, v0.z * f0.x);  // dx, ddx, dy, ddy
    vec4 d1 = vec4(v0.x * f1.y, v0.x * f1.z, v0.y * f1.x, v0.z * f1.x);
    vec4 fu1 = f0, fd0 = f1;
    for (int j = 1; j <= rf; ++j) {
        uint up = uint(max(y - j, 0)) * size.x + p.x;
        uint down = uint(min(y + 1 + j, last)) * size.x + p.x;
        vec4 fu0 = texelFetch(horizontal, int(plane + up));
        vec4 fd1 = texelFetch(horizontal, int(plane + down));
        vec3 w = texelFetch(weights, int(a.feature_offset) + rf + j).xyz;
        vec4 s0 = fu0 + fd0, s1 = fu1 + fd1;
        d0 += vec4(w.x * s0.y, w.x * s0.z, w.y * (fd0.x - fu0.x), w.z * s0.x);
        d1 += vec4(w.x * s1.y, w.x * s1.z, w.y * (fd1.x - fu1.x), w.z * s1.x);
        fu1 = fu0;
        fd0 = fd1;
    }
    resolve(here0, c0, d0, f0.w);
    if (y < last) resolve(here1, c1, d1, f1.w);
}
