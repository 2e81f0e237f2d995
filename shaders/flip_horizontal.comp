#version 450
// LDR-FLIP step 2: every row filtered at its columns' ppd: the colour kernels of Y', Cx and the
// two parts of Cz, and the feature Gaussian with its first and second derivative on the
// achromatic channel (Y' + 16) / 116. Clamp-to-edge, like the authors' code.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;

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
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, size))) return;
    FlipAxis a = flip_axis(axes, block_axis, block_offset + gl_WorkGroupID.x);
    uint row = p.y * size.x;
    int last = int(size.x) - 1;
    // The kernels are even (the derivative odd) about the centre (gpu_flip.cpp checks): each
    // pair of taps is one load of either neighbour and one weight, shared by both loops.
    int rc = a.colour_radius, rf = a.feature_radius;
    vec4 centre = texelFetch(opponent, int(row + p.x));
    vec4 colour = texelFetch(weights, int(a.colour_offset) + rc) * centre.xyzz;
    vec3 feature =
        texelFetch(weights, int(a.feature_offset) + rf).xyz * ((centre.x + 16.0) / 116.0);
    for (int i = 1; i <= max(rc, rf); ++i) {
        vec4 l = texelFetch(opponent, int(row) + max(int(p.x) - i, 0));
        vec4 r = texelFetch(opponent, int(row) + min(int(p.x) + i, last));
        if (i <= rc)
            colour += texelFetch(weights, int(a.colour_offset) + rc + i) * (l.xyzz + r.xyzz);
        if (i <= rf) {
            vec3 w = texelFetch(weights, int(a.feature_offset) + rf + i).xyz;
            float yl = (l.x + 16.0) / 116.0, yr = (r.x + 16.0) / 116.0;
            feature += vec3(w.x * (yl + yr), w.y * (yr - yl), w.z * (yl + yr));
        }
    }
    uint i = row + p.x;
    imageStore(horizontal, int(i), colour);
    imageStore(horizontal, int(size.x * size.y + i), vec4(feature, centre.w));
}
