#version 450
// LDR-FLIP step 2: every row filtered at its columns' ppd: the colour kernels of Y', Cx and the
// two parts of Cz, and the feature Gaussian with its first and second derivative on the
// achromatic channel (Y' + 16) / 116. Clamp-to-edge, like the authors' code.
#extension GL_GOOGLE_include_directive : require
// Four columns per invocation, each pixel's taps the left one's one column over, so every fetch of
// the opponent plane and of the weights serves four pixels. The workgroup's shape is
// gpu_flip.cpp's (several 16 x 16 blocks: each lane reads its own block's kernels; a multiple of
// 8 invocations wide, as llvmpipe runs a workgroup's rows in whole 8-lane vectors).
layout(local_size_x_id = 0, local_size_y_id = 1) in;

#include "flip_common.glsl"

// Read through texel buffers: llvmpipe turns a texel fetch into one vector gather, an SSBO load
// into a per-lane loop of bounds-checked scalar loads.
layout(set = 0, binding = 0) uniform samplerBuffer opponent;  // flip_prepare.comp's YCxCz, w
// Two planes: (y, cx, cz1, cz2) per pixel, then (g, dg, ddg, valid); a storage texel buffer.
layout(set = 0, binding = 1, rgba32f) uniform writeonly imageBuffer horizontal;
layout(set = 0, binding = 2) uniform usamplerBuffer axes;
layout(set = 0, binding = 3) uniform samplerBuffer weights;
// Per ppd field: ceil(width / 16) column blocks, then the row blocks.
layout(set = 0, binding = 4) uniform usamplerBuffer block_axis;

layout(push_constant) uniform Push {
    uvec2 size;
    uint block_offset;  // this ppd field's first column block in block_axis
};

float achromatic(vec4 o) { return (o.x + 16.0) / 116.0; }

vec3 feature_tap(vec3 w, vec4 l, vec4 r) {
    float yl = achromatic(l), yr = achromatic(r);
    return vec3(w.x * (yl + yr), w.y * (yr - yl), w.z * (yl + yr));
}

void main() {
    uvec2 p = uvec2(4u * gl_GlobalInvocationID.x, gl_GlobalInvocationID.y);  // and 3 to the right
    if (any(greaterThanEqual(p, size))) return;
    FlipAxis a = flip_axis(axes, block_axis, block_offset + p.x / kFlipBlock);
    int row = int(p.y * size.x);
    int last = int(size.x) - 1, x = int(p.x);
    // The kernels are even (the derivative odd) about the centre (gpu_flip.cpp checks): each
    // pair of taps is one load of either neighbour and one weight, shared by both loops. Pixel k
    // is column x + k (clamped; dropped when past the last column). At tap i pixel k needs
    // columns x + k -+ i (l_k, r_k): l_0 and r_3 are fetched, the others carried from tap i - 1.
    int rc = a.colour_radius, rf = a.feature_radius;
    vec4 h0 = texelFetch(opponent, row + x), h1 = texelFetch(opponent, row + min(x + 1, last));
    vec4 h2 = texelFetch(opponent, row + min(x + 2, last));
    vec4 h3 = texelFetch(opponent, row + min(x + 3, last));
    vec4 wc = texelFetch(weights, int(a.colour_offset) + rc);
    vec3 wf = texelFetch(weights, int(a.feature_offset) + rf).xyz;
    vec4 c0 = wc * h0.xyzz, c1 = wc * h1.xyzz, c2 = wc * h2.xyzz, c3 = wc * h3.xyzz;
    vec3 f0 = wf * achromatic(h0), f1 = wf * achromatic(h1), f2 = wf * achromatic(h2);
    vec3 f3 = wf * achromatic(h3);
    vec4 l1 = h0, l2 = h1, l3 = h2, r0 = h1, r1 = h2, r2 = h3;
    for (int i = 1; i <= max(rc, rf); ++i) {
        vec4 l0 = texelFetch(opponent, row + max(x - i, 0));
        vec4 r3 = texelFetch(opponent, row + min(x + 3 + i, last));
        if (i <= rc) {
            vec4 w = texelFetch(weights, int(a.colour_offset) + rc + i);
            c0 += w * (l0.xyzz + r0.xyzz);
            c1 += w * (l1.xyzz + r1.xyzz);
            c2 += w * (l2.xyzz + r2.xyzz);
            c3 += w * (l3.xyzz + r3.xyzz);
        }
        if (i <= rf) {
            vec3 w = texelFetch(weights, int(a.feature_offset) + rf + i).xyz;
            f0 += feature_tap(w, l0, r0);
            f1 += feature_tap(w, l1, r1);
            f2 += feature_tap(w, l2, r2);
            f3 += feature_tap(w, l3, r3);
        }
        l3 = l2;
        l2 = l1;
        l1 = l0;
        r0 = r1;
        r1 = r2;
        r2 = r3;
    }
    uint i = uint(row) + p.x, plane = size.x * size.y;
    imageStore(horizontal, int(i), c0);
    imageStore(horizontal, int(plane + i), vec4(f0, h0.w));
    if (x + 1 <= last) {
        imageStore(horizontal, int(i + 1u), c1);
        imageStore(horizontal, int(plane + i + 1u), vec4(f1, h1.w));
    }
    if (x + 2 <= last) {
        imageStore(horizontal, int(i + 2u), c2);
        imageStore(horizontal, int(plane + i + 2u), vec4(f2, h2.w));
    }
    if (x + 3 <= last) {
        imageStore(horizontal, int(i + 3u), c3);
        imageStore(horizontal, int(plane + i + 3u), vec4(f3, h3.w));
    }
}
