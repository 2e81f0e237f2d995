#version 450
// LDR-FLIP step 2: every row filtered at its columns' ppd: the colour kernels of Y', Cx and the
// two parts of Cz, and the feature Gaussian with its first and second derivative on the
// achromatic channel (Y' + 16) / 116. Clamp-to-edge, like the authors' code.
#extension GL_GOOGLE_include_directive : require
// Two columns per invocation (a workgroup is still one 16 x 16 block): the right pixel's taps are
// the left's one column over, so every fetch of the opponent plane and of the weights serves both.
layout(local_size_x = 8, local_size_y = 16) in;

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

void main() {
    uvec2 p = uvec2(2u * gl_GlobalInvocationID.x, gl_GlobalInvocationID.y);  // and p + (1, 0)
    if (any(greaterThanEqual(p, size))) return;
    FlipAxis a = flip_axis(axes, block_axis, block_offset + gl_WorkGroupID.x);
    int row = int(p.y * size.x);
    int last = int(size.x) - 1, x = int(p.x);
    // The kernels are even (the derivative odd) about the centre (gpu_flip.cpp checks): each
    // pair of taps is one load of either neighbour and one weight, shared by both loops. Pixel 0
    // is column x, pixel 1 column x + 1 (clamped; dropped when past the last column): at tap i
    // pixel 0 needs columns x -+ i, pixel 1 x + 1 -+ i: two fetches, two carried from tap i - 1.
    int rc = a.colour_radius, rf = a.feature_radius;
    vec4 centre0 = texelFetch(opponent, row + x);
    vec4 centre1 = texelFetch(opponent, row + min(x + 1, last));
    vec4 wc = texelFetch(weights, int(a.colour_offset) + rc);
    vec3 wf = texelFetch(weights, int(a.feature_offset) + rf).xyz;
    vec4 colour0 = wc * centre0.xyzz, colour1 = wc * centre1.xyzz;
    vec3 feature0 = wf * ((centre0.x + 16.0) / 116.0);
    vec3 feature1 = wf * ((centre1.x + 16.0) / 116.0);
    vec4 l1 = centre0, r0 = centre1;  // columns x + 1 - i, x + i
    for (int i = 1; i <= max(rc, rf); ++i) {
        vec4 l0 = texelFetch(opponent, row + max(x - i, 0));
        vec4 r1 = texelFetch(opponent, row + min(x + 1 + i, last));
        if (i <= rc) {
            vec4 w = texelFetch(weights, int(a.colour_offset) + rc + i);
            colour0 += w * (l0.xyzz + r0.xyzz);
            colour1 += w * (l1.xyzz + r1.xyzz);
        }
        if (i <= rf) {
            vec3 w = texelFetch(weights, int(a.feature_offset) + rf + i).xyz;
            float yl0 = (l0.x + 16.0) / 116.0, yr0 = (r0.x + 16.0) / 116.0;
            float yl1 = (l1.x + 16.0) / 116.0, yr1 = (r1.x + 16.0) / 116.0;
            feature0 += vec3(w.x * (yl0 + yr0), w.y * (yr0 - yl0), w.z * (yl0 + yr0));
            feature1 += vec3(w.x * (yl1 + yr1), w.y * (yr1 - yl1), w.z * (yl1 + yr1));
        }
        l1 = l0;
        r0 = r1;
    }
    uint i = uint(row) + p.x, plane = size.x * size.y;
    imageStore(horizontal, int(i), colour0);
    imageStore(horizontal, int(plane + i), vec4(feature0, centre0.w));
    if (x < last) {
        imageStore(horizontal, int(i + 1u), colour1);
        imageStore(horizontal, int(plane + i + 1u), vec4(feature1, centre1.w));
    }
}
