#version 450
// LDR-FLIP step 2: every row filtered at its columns' ppd: the colour kernels of Y', Cx and the
// two parts of Cz, and the feature Gaussian with its first and second derivative on the
// achromatic channel (Y' + 16) / 116. Clamp-to-edge, like the authors' code.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;

#include "flip_common.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Opponent { vec4 opponent[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Horizontal {
    vec4 horizontal[];  // 2 per pixel: (y, cx, cz1, cz2), (g, dg, ddg, valid)
};
layout(std430, set = 0, binding = 2) readonly buffer Axes { FlipAxis axes[]; };
layout(std430, set = 0, binding = 3) readonly buffer Weights { vec4 weights[]; };
layout(std430, set = 0, binding = 4) readonly buffer BlockAxis {
    uint block_axis[];  // per ppd field: ceil(width / 16) column blocks, then the row blocks
};

layout(push_constant) uniform Push {
    uvec2 size;
    uint block_offset;  // this ppd field's first column block in block_axis
};

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, size))) return;
    FlipAxis a = axes[block_axis[block_offset + gl_WorkGroupID.x]];
    uint row = p.y * size.x;
    int last = int(size.x) - 1;
    vec4 colour = vec4(0.0);
    for (int i = -a.colour_radius; i <= a.colour_radius; ++i) {
        vec4 o = opponent[row + uint(clamp(int(p.x) + i, 0, last))];
        colour += weights[a.colour_offset + uint(i + a.colour_radius)] * o.xyzz;
    }
    vec3 feature = vec3(0.0);
    for (int i = -a.feature_radius; i <= a.feature_radius; ++i) {
        float y = (opponent[row + uint(clamp(int(p.x) + i, 0, last))].x + 16.0) / 116.0;
        feature += weights[a.feature_offset + uint(i + a.feature_radius)].xyz * y;
    }
    uint i = row + p.x;
    horizontal[2u * i] = colour;
    horizontal[2u * i + 1u] = vec4(feature, opponent[i].w);
}
